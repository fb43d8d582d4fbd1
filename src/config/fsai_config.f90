!> Deck groups of the sparse approximate inverses (see fsai_params.f90 for
!> the meaning of each setting):
!>
!> &afsai: the adaptive FSAI preconditioners (k_precon, flux_precon or
!>   schur_precon = 'afsai' in &solver)
!>   max_steps  adaptive steps per row, >= 0                              [5]
!>   step_size  entries added per row and step, >= 1                      [4]
!>   tol        stop a row when a step improves it by less, >= 0       [1e-4]
!>   init       start pattern: 'lower' (lower triangle of the matrix) or
!>              'diagonal'                                            ['lower']
!>   drop       drop entries below drop * the row's largest, in [0, 1)    [0]
!>
!> &block_fsai: the explicit decoupling factors F ~ K^-1 Q, A^-1 B and the
!>   explicit Schur complement (decoupling = 'explicit' in &solver)
!>   max_steps, step_size, tol, drop  as above, per column of F; tol is the
!>              relative residual of a column           [4, 6, 1e-2, 0]
!>   schur_drop drop entries of the explicit Schur complement with
!>              |s_ij| < schur_drop sqrt(|s_ii s_jj|), >= 0             [1e-3]
module fsai_config
  use kinds, only: rp, msg_len, name_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len
  use strings, only: itoa, rtoa
  use fsai_params, only: fsai_params_t
  use param_group, only: param_group_t
  implicit none
  private

  public :: fsai_config_t

  type :: fsai_config_t
    type(fsai_params_t) :: precon           !< &afsai
    type(fsai_params_t) :: factor           !< &block_fsai
    real(rp) :: schur_drop = 1.0e-3_rp
  contains
    procedure :: read => read_fsai_config
    procedure :: describe => describe_fsai_config
  end type fsai_config_t

contains

  !> Read and check &afsai and &block_fsai (both optional).
  subroutine read_fsai_config(self, d, log, status)
    class(fsai_config_t), intent(inout) :: self
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(error_status_t), intent(inout) :: status
    integer :: max_steps, step_size, ios
    real(rp) :: tol, drop, schur_drop
    character(len=name_len) :: init
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /afsai/ max_steps, step_size, tol, init, drop
    namelist /block_fsai/ max_steps, step_size, tol, drop, schur_drop

    self%factor%max_steps = 4
    self%factor%step_size = 6
    self%factor%tol = 1.0e-2_rp
    self%factor%drop = 0.0_rp
    max_steps = self%precon%max_steps; step_size = self%precon%step_size; tol = self%precon%tol
    init = self%precon%init; drop = self%precon%drop
    if (d%count('afsai') > 0) then
      call d%block('afsai', 1, b)
      read(b, nml=afsai, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('afsai', 1, ios, msg, status)
        return
      end if
    end if
    call check('afsai')
    if (init /= 'lower' .and. init /= 'diagonal') &
      call d%fail(status, 'afsai', 1, 'init', "must be 'lower' or 'diagonal' (got '"//trim(init)//"')")
    if (.not. status%ok()) return
    self%precon%max_steps = max_steps; self%precon%step_size = step_size; self%precon%tol = tol
    self%precon%init = init; self%precon%drop = drop

    max_steps = self%factor%max_steps; step_size = self%factor%step_size; tol = self%factor%tol
    drop = self%factor%drop; schur_drop = self%schur_drop
    if (d%count('block_fsai') > 0) then
      call d%block('block_fsai', 1, b)
      read(b, nml=block_fsai, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('block_fsai', 1, ios, msg, status)
        return
      end if
    end if
    call check('block_fsai')
    if (.not. (schur_drop >= 0.0_rp)) &
      call d%fail(status, 'block_fsai', 1, 'schur_drop', 'must be >= 0 (got '//rtoa(schur_drop)//')')
    if (.not. status%ok()) return
    self%factor%max_steps = max_steps; self%factor%step_size = step_size; self%factor%tol = tol
    self%factor%drop = drop; self%schur_drop = schur_drop
  contains
    subroutine check(group)
      character(len=*), intent(in) :: group
      if (max_steps < 0) call d%fail(status, group, 1, 'max_steps', 'must be >= 0 (got '//itoa(max_steps)//')')
      if (step_size < 1) call d%fail(status, group, 1, 'step_size', 'must be >= 1 (got '//itoa(step_size)//')')
      if (.not. (tol >= 0.0_rp)) call d%fail(status, group, 1, 'tol', 'must be >= 0 (got '//rtoa(tol)//')')
      if (.not. (drop >= 0.0_rp .and. drop < 1.0_rp)) &
        call d%fail(status, group, 1, 'drop', 'must lie in [0, 1) (got '//rtoa(drop)//')')
    end subroutine check
  end subroutine read_fsai_config

  subroutine describe_fsai_config(self, afsai, block_fsai)
    class(fsai_config_t), intent(in) :: self
    type(param_group_t), intent(out) :: afsai, block_fsai
    call afsai%init('afsai', "our adaptive FSAI preconditioner (&solver precon, k_precon, flux_precon or "// &
                    "schur_precon = 'afsai'; the steps, step size and tol also for 'hypre_fsai')")
    call afsai%add('max_steps', self%precon%max_steps, '-', 'adaptive steps per row', '>= 0')
    call afsai%add('step_size', self%precon%step_size, '-', 'entries added per row and step', '>= 1')
    call afsai%add('tol', self%precon%tol, '-', 'a row stops when a step improves its Kaporin measure by less', &
                   '>= 0')
    call afsai%add('init', self%precon%init, '-', 'start pattern: the lower triangle of the matrix, or its '// &
                   'diagonal', "'lower' or 'diagonal'")
    call afsai%add('drop', self%precon%drop, '-', "drop entries below drop times the row's largest", '[0, 1)')
    call block_fsai%init('block_fsai', "biot, &solver decoupling = 'explicit': the block aFSAI decoupling "// &
                         'factors F ~ K^-1 Q, A^-1 B and the explicit Schur complement')
    call block_fsai%add('max_steps', self%factor%max_steps, '-', 'adaptive steps per column of F', '>= 0')
    call block_fsai%add('step_size', self%factor%step_size, '-', 'positions added per column and step (the '// &
                        'largest residual components)', '>= 1')
    call block_fsai%add('tol', self%factor%tol, '-', 'a column stops at this relative residual', '>= 0')
    call block_fsai%add('drop', self%factor%drop, '-', "drop entries below drop times the column's largest", &
                        '[0, 1)')
    call block_fsai%add('schur_drop', self%schur_drop, '-', 'drop entries of the explicit Schur complement with '// &
                        '|s_ij| < schur_drop sqrt(|s_ii s_jj|)', '>= 0')
  end subroutine describe_fsai_config
end module fsai_config
