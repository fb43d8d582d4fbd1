!> Deck group &pressure_change (any number; elasticity and contact): a
!> change of pore pressure over a region, given rather than solved for (a
!> one-way coupling: the pressures of a reservoir simulator, a depletion).
!> The rock feels it through its Biot coefficient (&material biot): the
!> load of integral b dp div(eta); the faults' faces inside or beside the
!> region feel it as fault pressure (the mean of the changes of the two
!> cells an element joins). The change grows with the load factor like the
!> other loads, times an optional history.
!>
!>   region    name of the mesh region                               [required]
!>   value     the change of pore pressure at full load [Pa] (negative:
!>             depletion)                                            [required]
!>   history   file of "time factor" rows (# comments) that multiplies
!>             value, as history in &boundary                        ['']
!>   point(3)  restricts the change to the fault block of the region
!>             that holds this point [m]: the cells of the region that
!>             faces not on a fault join to the point's cell (a sealed
!>             compartment: a fault that cuts through the region bounds
!>             it, one that ends inside it does not). A region takes
!>             either one group without a point or groups with points in
!>             different blocks                          [unset: the region]
module pressure_change_config
  use kinds, only: rp, name_len, msg_len, path_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len, unset_real
  use param_group, only: param_group_t
  use history_file, only: read_history, history_factor
  use os_services, only: absolute_path
  implicit none
  private

  public :: pressure_change_config_t, read_pressure_changes, load_pressure_change_histories

  type :: pressure_change_config_t
    character(len=name_len) :: region = ''
    real(rp) :: value = 0.0_rp                      !< [Pa] at full load
    character(len=path_len) :: history = ''
    logical :: has_point = .false.                  !< point given: one fault block of the region
    real(rp) :: point(3) = 0.0_rp                   !< [m] a point of that block
    real(rp), allocatable :: hist_t(:), hist_f(:)   !< the history, once loaded
  contains
    procedure :: describe => describe_pressure_change
    procedure :: factor
  end type pressure_change_config_t

contains

  !> Read every &pressure_change group; at most one per region.
  subroutine read_pressure_changes(d, log, pcs, status)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(pressure_change_config_t), allocatable, intent(out) :: pcs(:)
    type(error_status_t), intent(inout) :: status
    character(len=name_len) :: region
    character(len=path_len) :: history
    real(rp) :: value, point(3)
    integer :: k, j, ios
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /pressure_change/ region, value, history, point
    allocate(pcs(d%count('pressure_change')))
    do k = 1, size(pcs)
      region = ''
      value = unset_real
      history = ''
      point = unset_real
      call d%block('pressure_change', k, b)
      read(b, nml=pressure_change, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('pressure_change', k, ios, msg, status)
        return
      end if
      if (len_trim(region) == 0) call d%fail(status, 'pressure_change', k, 'region', 'required')
      if (value == unset_real) call d%fail(status, 'pressure_change', k, 'value', 'required')
      if (any(point == unset_real) .and. any(point /= unset_real)) &
        call d%fail(status, 'pressure_change', k, 'point', 'needs its three coordinates')
      pcs(k)%has_point = all(point /= unset_real)
      ! a region: one group for all of it, or groups for some of its blocks
      do j = 1, k - 1
        if (pcs(j)%region /= region) cycle
        if (.not. (pcs(k)%has_point .and. pcs(j)%has_point)) then
          call d%fail(status, 'pressure_change', k, 'region', "region '"//trim(region)// &
            "' already has a &pressure_change (several groups on one region need a point each, in different"// &
            " fault blocks)")
          exit
        end if
      end do
      if (.not. status%ok()) return
      if (pcs(k)%has_point) pcs(k)%point = point
      pcs(k)%region = region
      pcs(k)%value = value
      call d%input_path('pressure_change', k, 'history', history, pcs(k)%history, status)
      if (.not. status%ok()) return
    end do
  end subroutine read_pressure_changes

  !> Read the history files (rank 0) and broadcast them. Collective.
  subroutine load_pressure_change_histories(comm, pcs, status)
    type(parallel_comm_t), intent(in) :: comm
    type(pressure_change_config_t), intent(inout) :: pcs(:)
    type(error_status_t), intent(inout) :: status
    integer :: k
    character(len=msg_len) :: msg
    do k = 1, size(pcs)
      if (len_trim(pcs(k)%history) == 0) cycle
      call read_history(comm, pcs(k)%history, pcs(k)%hist_t, pcs(k)%hist_f, msg)
      if (len_trim(msg) > 0) then
        call status%set("&pressure_change on region '"//trim(pcs(k)%region)//"': history file '"// &
                        trim(pcs(k)%history)//"': "//trim(msg), 1)
        return
      end if
    end do
  end subroutine load_pressure_change_histories

  !> The history's factor at time (load factor) t: 1 without a history.
  real(rp) function factor(self, t)
    class(pressure_change_config_t), intent(in) :: self
    real(rp), intent(in) :: t
    factor = 1.0_rp
    if (allocated(self%hist_t)) factor = history_factor(self%hist_t, self%hist_f, t)
  end function factor

  subroutine describe_pressure_change(self, g)
    class(pressure_change_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: g
    call g%init('pressure_change', 'a given change of pore pressure over a region (a depletion, a reservoir '// &
                "simulator's pressures), felt through &material biot and on the faults' faces")
    call g%add('region', self%region, '-', 'mesh region', 'a region of the mesh')
    call g%add('value', self%value, 'Pa', 'change of pore pressure at full load, grown with the load like the '// &
               'other loads (negative: depletion)')
    call g%add('history', absolute_path(self%history), '-', "file of 'time factor' rows scaling value ('': none)")
    call g%add_optional('point', self%has_point, self%point, '(none: all of the region)', 'm', 'restricts the '// &
                        'change to the fault block of the region that holds this point', 'inside the region')
  end subroutine describe_pressure_change
end module pressure_change_config
