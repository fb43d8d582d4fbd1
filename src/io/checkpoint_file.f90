!> Checkpoint files: everything a run needs to go on from the end of a step,
!> in ONE HDF5 file.
!>
!>   root attributes  format ('geoblock checkpoint'), format_version (1),
!>                    physics, n_ranks, step (the last completed step), time
!>                    (its end, or load factor), known_steps (load steps of the
!>                    run, 0 for time steps), next_dt (the nominal size of the
!>                    next step as the writing run's schedule gave it, 0 when
!>                    the run was over), last_dt, n_outputs (output steps
!>                    written so far)
!>   /rank_NNNN       the physics' state record of rank NNNN (0-based, four
!>                    digits): one 1-D dataset per named array, the rank's local
!>                    arrays as the physics keeps them
!>   /output          the output's index (which output steps exist, their times
!>                    and fields), so that a restarted run continues the XDMF
!>                    time series; only when the run writes fields
!>
!> Writing: the ranks write their groups one after the other with serial
!> HDF5 (rank 0 creates the file with the attributes and /output, then each
!> rank in turn opens it, adds its group and closes it), so no rank gathers
!> another's state and no parallel HDF5 is needed; a checkpoint is small next
!> to the field output. Everything goes to <path>.tmp, which rank 0 renames
!> to <path> once every rank has written: a run killed while writing leaves
!> the previous checkpoint intact.
!>
!> Reading: rank 0 checks the file (exists, is HDF5, is a checkpoint, of the
!> right physics and number of ranks) and every rank learns the verdict; then
!> each rank reads its own group and /output. Every error is one line that
!> names the file. Both directions are collective, with the same status on
!> every rank.
module checkpoint_file
  use kinds, only: rp, name_len, path_len, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use status_sync, only: agree
  use strings, only: itoa
  use os_services, only: path_kind, path_missing, path_directory, rename_path
  use state_record, only: state_record_t
  use h5_record, only: h5_record_file_t, is_hdf5_file
  implicit none
  private

  public :: checkpoint_info_t, write_checkpoint, read_checkpoint

  character(len=*), parameter :: format_name = 'geoblock checkpoint'
  integer, parameter :: format_version = 1

  !> The run's loop state kept beside the physics' records.
  type :: checkpoint_info_t
    character(len=name_len) :: physics = ''
    integer :: n_ranks = 0
    integer :: step = 0                 !< the last completed step
    real(rp) :: time = 0.0_rp           !< its end time (load factor)
    integer :: known_steps = 0          !< load steps of the run (0: time steps)
    real(rp) :: next_dt = 0.0_rp        !< nominal size of the next step (0: the run was over)
    real(rp) :: last_dt = 0.0_rp        !< size of the last (sub-)step taken
    integer :: n_outputs = 0            !< output steps written
  end type checkpoint_info_t

contains

  !> Write the checkpoint at path: info, this rank's record st and the output
  !> index (has_index: the run writes fields; the same on every rank, rank
  !> 0's is written). Collective; status agrees.
  subroutine write_checkpoint(comm, path, info, st, has_index, out_index, status)
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: path
    type(checkpoint_info_t), intent(in) :: info
    type(state_record_t), intent(in) :: st, out_index
    logical, intent(in) :: has_index
    type(error_status_t), intent(inout) :: status
    type(h5_record_file_t) :: f
    character(len=path_len) :: tmp
    integer :: r
    tmp = trim(path)//'.tmp'
    if (comm%is_root()) then
      call f%create(tmp, status)
      if (status%ok()) call write_header(f, info, status)
      if (status%ok() .and. has_index) call f%write_record('output', out_index, status)
      call f%close(status)
    end if
    call agree(comm, status)
    do r = 0, comm%size - 1
      if (.not. status%ok()) exit
      if (comm%rank == r) then
        call f%open(tmp, .true., status)
        if (status%ok()) call f%write_record(trim(rank_group(r)), st, status)
        call f%close(status)
      end if
      call agree(comm, status)
    end do
    if (comm%is_root() .and. status%ok()) call rename_path(tmp, path, status)
    call agree(comm, status)
    if (.not. status%ok()) status%msg = 'checkpoint: '//trim(status%msg)
  end subroutine write_checkpoint

  subroutine write_header(f, info, status)
    type(h5_record_file_t), intent(inout) :: f
    type(checkpoint_info_t), intent(in) :: info
    type(error_status_t), intent(inout) :: status
    call f%put_attr_text('format', format_name, status)
    if (status%ok()) call f%put_attr_int('format_version', format_version, status)
    if (status%ok()) call f%put_attr_text('physics', info%physics, status)
    if (status%ok()) call f%put_attr_int('n_ranks', info%n_ranks, status)
    if (status%ok()) call f%put_attr_int('step', info%step, status)
    if (status%ok()) call f%put_attr_real('time', info%time, status)
    if (status%ok()) call f%put_attr_int('known_steps', info%known_steps, status)
    if (status%ok()) call f%put_attr_real('next_dt', info%next_dt, status)
    if (status%ok()) call f%put_attr_real('last_dt', info%last_dt, status)
    if (status%ok()) call f%put_attr_int('n_outputs', info%n_outputs, status)
  end subroutine write_header

  !> Read the checkpoint at path for a run of physics on comm: its info,
  !> this rank's record st and the output index (has_index: the file has
  !> one). Collective; status agrees and names the file.
  subroutine read_checkpoint(comm, path, physics, info, st, has_index, out_index, status)
    type(parallel_comm_t), intent(in) :: comm
    character(len=*), intent(in) :: path, physics
    type(checkpoint_info_t), intent(out) :: info
    type(state_record_t), intent(inout) :: st, out_index
    logical, intent(out) :: has_index
    type(error_status_t), intent(inout) :: status
    type(h5_record_file_t) :: f
    integer :: flag
    if (comm%is_root()) call check_header(path, physics, comm%size, info, status)
    call agree(comm, status)
    if (status%ok()) call share_info(comm, info)
    has_index = .false.
    if (status%ok()) then
      call f%open(path, .false., status)
      if (status%ok()) call f%read_record(trim(rank_group(comm%rank)), st, status)
      has_index = f%has_group('output')
      if (status%ok() .and. has_index) call f%read_record('output', out_index, status)
      call f%close(status)
    end if
    call agree(comm, status)
    flag = merge(1, 0, has_index)
    call comm%bcast(flag)
    has_index = flag == 1
    if (.not. status%ok() .and. index(status%msg, trim(path)) == 0) &
      status%msg = "restart file '"//trim(path)//"': "//trim(status%msg)
  end subroutine read_checkpoint

  !> Rank 0: the file is a checkpoint of this physics on n_ranks ranks; info
  !> from its attributes.
  subroutine check_header(path, physics, n_ranks, info, status)
    character(len=*), intent(in) :: path, physics
    integer, intent(in) :: n_ranks
    type(checkpoint_info_t), intent(inout) :: info
    type(error_status_t), intent(inout) :: status
    type(h5_record_file_t) :: f
    character(len=name_len) :: fmt
    character(len=msg_len) :: what
    integer :: version
    what = "restart file '"//trim(path)//"'"
    select case (path_kind(path))
    case (path_missing)
      call status%set(trim(what)//' does not exist')
      return
    case (path_directory)
      call status%set(trim(what)//' is a directory, not a checkpoint file')
      return
    end select
    if (.not. is_hdf5_file(path)) then
      call status%set(trim(what)//' is not an HDF5 file (not a geoblock checkpoint)')
      return
    end if
    call f%open(path, .false., status)
    if (.not. status%ok()) return
    fmt = ''
    if (f%has_attr('format')) call f%get_attr_text('format', fmt, status)
    if (fmt /= format_name) then
      call status%set(trim(what)//" is an HDF5 file but not a geoblock checkpoint (no format = '"//format_name//"')")
    else
      call f%get_attr_int('format_version', version, status)
      if (status%ok() .and. version /= format_version) call status%set(trim(what)//' has format version '// &
        itoa(version)//', this geoblock reads version '//itoa(format_version))
    end if
    if (status%ok()) call read_info(f, info, status)
    if (status%ok() .and. info%physics /= physics) call status%set(trim(what)//" was written by physics = '"// &
      trim(info%physics)//"', this run is physics = '"//trim(physics)//"'")
    if (status%ok() .and. info%n_ranks /= n_ranks) call status%set(trim(what)//' was written on '// &
      itoa(info%n_ranks)//' ranks, this run has '//itoa(n_ranks)//' (a checkpoint resumes on the same number of ranks)')
    call f%close(status)
  end subroutine check_header

  subroutine read_info(f, info, status)
    type(h5_record_file_t), intent(inout) :: f
    type(checkpoint_info_t), intent(inout) :: info
    type(error_status_t), intent(inout) :: status
    call f%get_attr_text('physics', info%physics, status)
    if (status%ok()) call f%get_attr_int('n_ranks', info%n_ranks, status)
    if (status%ok()) call f%get_attr_int('step', info%step, status)
    if (status%ok()) call f%get_attr_real('time', info%time, status)
    if (status%ok()) call f%get_attr_int('known_steps', info%known_steps, status)
    if (status%ok()) call f%get_attr_real('next_dt', info%next_dt, status)
    if (status%ok()) call f%get_attr_real('last_dt', info%last_dt, status)
    if (status%ok()) call f%get_attr_int('n_outputs', info%n_outputs, status)
  end subroutine read_info

  !> Rank 0's info to every rank.
  subroutine share_info(comm, info)
    type(parallel_comm_t), intent(in) :: comm
    type(checkpoint_info_t), intent(inout) :: info
    call comm%bcast(info%physics)
    call comm%bcast(info%n_ranks)
    call comm%bcast(info%step)
    call comm%bcast(info%time)
    call comm%bcast(info%known_steps)
    call comm%bcast(info%next_dt)
    call comm%bcast(info%last_dt)
    call comm%bcast(info%n_outputs)
  end subroutine share_info

  !> Name of rank r's group.
  function rank_group(r) result(g)
    integer, intent(in) :: r
    character(len=16) :: g
    if (r < 10000) then
      write(g, '(a,i4.4)') 'rank_', r
    else
      write(g, '(a,i0)') 'rank_', r
    end if
  end function rank_group
end module checkpoint_file
