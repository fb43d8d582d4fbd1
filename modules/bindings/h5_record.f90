!> One process's view of an HDF5 file of state records: a record
!> (state_record_t) becomes a group with one 1-D dataset per entry (float64,
!> int32, or fixed-length strings of name_len characters for text), and the
!> file's root carries scalar attributes (integer, real, text).
!>
!> Unlike xdmf_writer, which writes through MPI-IO with every rank at once,
!> this file is opened by one process at a time with HDF5's default (POSIX)
!> driver: the caller decides who opens it and in which order (checkpoint_file
!> lets the ranks write their groups one after the other). Nothing here is
!> collective. HDF5's own error printing is switched off while a file is
!> open, since every failure comes back as a status naming the file.
module h5_record
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_char, c_null_ptr
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5fcreate_f, h5fopen_f, h5fclose_f, h5fis_hdf5_f, &
                  H5F_ACC_TRUNC_F, H5F_ACC_RDWR_F, H5F_ACC_RDONLY_F, h5eset_auto_f, &
                  h5screate_simple_f, h5screate_f, H5S_SCALAR_F, h5sclose_f, h5sget_simple_extent_npoints_f, &
                  h5dcreate_f, h5dopen_f, h5dclose_f, h5dwrite_f, h5dread_f, h5dget_space_f, h5dget_type_f, &
                  h5acreate_f, h5aopen_f, h5awrite_f, h5aread_f, h5aclose_f, h5aget_type_f, h5aexists_f, &
                  h5gcreate_f, h5gopen_f, h5gclose_f, h5gn_members_f, h5gget_obj_info_idx_f, h5lexists_f, &
                  h5tcopy_f, h5tset_size_f, h5tget_size_f, h5tget_class_f, h5tclose_f, H5T_FORTRAN_S1, &
                  H5T_STRING_F, H5T_FLOAT_F, H5T_INTEGER_F, H5G_DATASET_F, &
                  h5kind_to_type, H5_REAL_KIND, H5_INTEGER_KIND, H5T_IEEE_F64LE, H5T_STD_I32LE
  use kinds, only: rp, name_len, path_len
  use error_status, only: error_status_t
  use state_record, only: state_record_t
  implicit none
  private

  public :: h5_record_file_t, is_hdf5_file

  !> An open file (or none: id < 0).
  type :: h5_record_file_t
    integer(hid_t) :: id = -1
    character(len=path_len) :: path = ''
  contains
    procedure :: create
    procedure :: open
    procedure :: close
    procedure :: has_attr
    procedure :: has_group
    procedure :: put_attr_int, put_attr_real, put_attr_text
    procedure :: get_attr_int, get_attr_real, get_attr_text
    procedure :: write_record
    procedure :: read_record
  end type h5_record_file_t

contains

  !> The file at path exists and is an HDF5 file.
  logical function is_hdf5_file(path)
    character(len=*), intent(in) :: path
    integer :: err
    call quiet()
    is_hdf5_file = .false.
    call h5fis_hdf5_f(trim(path), is_hdf5_file, err)
    if (err /= 0) is_hdf5_file = .false.
    call h5eset_auto_f(1, err)
  end function is_hdf5_file

  !> Initialise HDF5 (again: harmless) and silence its error printing.
  subroutine quiet()
    integer :: err
    call h5open_f(err)
    call h5eset_auto_f(0, err)
  end subroutine quiet

  !> Create (truncate) the file at path, open for writing.
  subroutine create(self, path, status)
    class(h5_record_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    type(error_status_t), intent(inout) :: status
    integer :: err
    call quiet()
    self%path = path
    call h5fcreate_f(trim(path), H5F_ACC_TRUNC_F, self%id, err)
    if (err /= 0) then
      self%id = -1
      call status%set("cannot create the HDF5 file '"//trim(path)//"'")
    end if
  end subroutine create

  !> Open the existing file at path, for reading only or also for writing.
  subroutine open(self, path, writable, status)
    class(h5_record_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    logical, intent(in) :: writable
    type(error_status_t), intent(inout) :: status
    integer :: err
    call quiet()
    self%path = path
    if (writable) then
      call h5fopen_f(trim(path), H5F_ACC_RDWR_F, self%id, err)
    else
      call h5fopen_f(trim(path), H5F_ACC_RDONLY_F, self%id, err)
    end if
    if (err /= 0) then
      self%id = -1
      call status%set("cannot open the HDF5 file '"//trim(path)//"'")
    end if
  end subroutine open

  !> Close the file (a file that is not open is left alone); status only
  !> reports a failure when it is still ok.
  subroutine close(self, status)
    class(h5_record_file_t), intent(inout) :: self
    type(error_status_t), intent(inout) :: status
    integer :: err
    if (self%id < 0) return
    call h5fclose_f(self%id, err)
    self%id = -1
    if (err /= 0 .and. status%ok()) call status%set("cannot close the HDF5 file '"//trim(self%path)//"'")
    call h5eset_auto_f(1, err)
  end subroutine close

  !> The root has an attribute called name.
  logical function has_attr(self, name)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer :: err
    call h5aexists_f(self%id, name, has_attr, err)
    if (err /= 0) has_attr = .false.
  end function has_attr

  !> The file has a group (or any object) at the root called name.
  logical function has_group(self, name)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer :: err
    call h5lexists_f(self%id, name, has_group, err)
    if (err /= 0) has_group = .false.
  end function has_group

  ! ---- root attributes -------------------------------------------------------

  subroutine put_attr_int(self, name, v, status)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: v
    type(error_status_t), intent(inout) :: status
    integer, target :: buf
    buf = v
    call attr_io(self, name, .true., h5kind_to_type(kind(buf), H5_INTEGER_KIND), H5T_STD_I32LE, c_loc(buf), &
                 status)
  end subroutine put_attr_int

  subroutine put_attr_real(self, name, v, status)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(in) :: v
    type(error_status_t), intent(inout) :: status
    real(rp), target :: buf
    buf = v
    call attr_io(self, name, .true., h5kind_to_type(rp, H5_REAL_KIND), H5T_IEEE_F64LE, c_loc(buf), status)
  end subroutine put_attr_real

  !> A text attribute of len_trim(v) characters (at least one).
  subroutine put_attr_text(self, name, v, status)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: name, v
    type(error_status_t), intent(inout) :: status
    character(kind=c_char), allocatable, target :: buf(:)
    integer(hid_t) :: t
    integer :: n, err
    n = max(1, len_trim(v))
    allocate(buf(n))
    buf = ' '
    buf(1:len_trim(v)) = transfer(trim(v), buf, len_trim(v))
    call text_type(n, t, err)
    call attr_io(self, name, .true., t, t, c_loc(buf), status)
    call h5tclose_f(t, err)
  end subroutine put_attr_text

  subroutine get_attr_int(self, name, v, status)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer, intent(out) :: v
    type(error_status_t), intent(inout) :: status
    integer, target :: buf
    buf = 0
    call attr_io(self, name, .false., h5kind_to_type(kind(buf), H5_INTEGER_KIND), -1_hid_t, c_loc(buf), status)
    v = buf
  end subroutine get_attr_int

  subroutine get_attr_real(self, name, v, status)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: name
    real(rp), intent(out) :: v
    type(error_status_t), intent(inout) :: status
    real(rp), target :: buf
    buf = 0.0_rp
    call attr_io(self, name, .false., h5kind_to_type(rp, H5_REAL_KIND), -1_hid_t, c_loc(buf), status)
    v = buf
  end subroutine get_attr_real

  !> A text attribute into v (cut to len(v); '' when it is no text).
  subroutine get_attr_text(self, name, v, status)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: name
    character(len=*), intent(out) :: v
    type(error_status_t), intent(inout) :: status
    character(kind=c_char), allocatable, target :: buf(:)
    integer(hid_t) :: attr, ft, mt
    integer(size_t) :: n
    integer :: err, cls, i
    type(c_ptr) :: p
    v = ''
    call h5aopen_f(self%id, name, attr, err)
    if (err /= 0) then
      call status%set("HDF5 file '"//trim(self%path)//"' has no attribute '"//name//"'")
      return
    end if
    call h5aget_type_f(attr, ft, err)
    call h5tget_class_f(ft, cls, err)
    call h5tget_size_f(ft, n, err)
    call h5tclose_f(ft, err)
    if (cls == H5T_STRING_F .and. n > 0) then
      allocate(buf(n))
      call text_type(int(n), mt, err)
      p = c_loc(buf)
      call h5aread_f(attr, mt, p, err)
      call h5tclose_f(mt, err)
      do i = 1, min(int(n), len(v))
        if (buf(i) == achar(0)) exit
        v(i:i) = buf(i)
      end do
    end if
    call h5aclose_f(attr, err)
  end subroutine get_attr_text

  !> Write (put) or read a scalar attribute of the root through buf.
  subroutine attr_io(self, name, put, mem_type, file_type, buf, status)
    type(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: name
    logical, intent(in) :: put
    integer(hid_t), intent(in) :: mem_type, file_type
    type(c_ptr), intent(in) :: buf
    type(error_status_t), intent(inout) :: status
    integer(hid_t) :: space, attr
    integer :: err, err2
    type(c_ptr) :: p
    space = -1
    attr = -1
    steps: block
      if (put) then
        call h5screate_f(H5S_SCALAR_F, space, err)
        if (err /= 0) exit steps
        call h5acreate_f(self%id, name, file_type, space, attr, err)
        if (err /= 0) exit steps
        call h5awrite_f(attr, mem_type, buf, err)
      else
        call h5aopen_f(self%id, name, attr, err)
        if (err /= 0) then
          call status%set("HDF5 file '"//trim(self%path)//"' has no attribute '"//name//"'")
          return
        end if
        p = buf
        call h5aread_f(attr, mem_type, p, err)
      end if
    end block steps
    if (err /= 0 .and. put) call status%set("cannot write attribute '"//name//"' to '"//trim(self%path)//"'")
    if (err /= 0 .and. .not. put) call status%set("cannot read attribute '"//name//"' of '"//trim(self%path)//"'")
    if (attr >= 0) call h5aclose_f(attr, err2)
    if (space >= 0) call h5sclose_f(space, err2)
  end subroutine attr_io

  !> A fixed-length string type of n characters (close it after use).
  subroutine text_type(n, t, err)
    integer, intent(in) :: n
    integer(hid_t), intent(out) :: t
    integer, intent(out) :: err
    call h5tcopy_f(H5T_FORTRAN_S1, t, err)
    if (err == 0) call h5tset_size_f(t, int(n, size_t), err)
  end subroutine text_type

  ! ---- records ---------------------------------------------------------------

  !> Write every entry of st as a dataset of the new group `group`.
  subroutine write_record(self, group, st, status)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: group
    type(state_record_t), intent(in) :: st
    type(error_status_t), intent(inout) :: status
    integer(hid_t) :: g, t
    integer :: k, err, err2
    character(kind=c_char), allocatable, target :: text(:)
    call h5gcreate_f(self%id, group, g, err)
    if (err /= 0) then
      call status%set("cannot create group /"//group//" in '"//trim(self%path)//"'")
      return
    end if
    do k = 1, st%n
      associate (e => st%e(k))
        if (allocated(e%r)) then
          call write_array(g, e%name, size(e%r), h5kind_to_type(rp, H5_REAL_KIND), H5T_IEEE_F64LE, r_ptr(e%r), err)
        else if (allocated(e%i)) then
          call write_array(g, e%name, size(e%i), h5kind_to_type(kind(e%i), H5_INTEGER_KIND), H5T_STD_I32LE, &
                           i_ptr(e%i), err)
        else if (allocated(e%s)) then
          allocate(text(max(1, size(e%s) * name_len)))
          if (size(e%s) > 0) text = transfer(e%s, text, size(e%s) * name_len)
          call text_type(name_len, t, err)
          call write_array(g, e%name, size(e%s), t, t, c_loc(text), err)
          call h5tclose_f(t, err2)
          deallocate(text)
        else
          err = 0
        end if
      end associate
      if (err /= 0) then
        call status%set("cannot write dataset /"//group//"/"//trim(st%e(k)%name)//" to '"//trim(self%path)//"'")
        exit
      end if
    end do
    call h5gclose_f(g, err)
  end subroutine write_record

  !> A 1-D dataset of n values (no data written when n = 0).
  subroutine write_array(loc, name, n, mem_type, file_type, buf, err)
    integer(hid_t), intent(in) :: loc, mem_type, file_type
    character(len=*), intent(in) :: name
    integer, intent(in) :: n
    type(c_ptr), intent(in) :: buf
    integer, intent(out) :: err
    integer(hid_t) :: space, dset
    integer :: err2
    call h5screate_simple_f(1, [int(n, hsize_t)], space, err)
    if (err /= 0) return
    call h5dcreate_f(loc, trim(name), file_type, space, dset, err)
    if (err == 0) then
      if (n > 0) call h5dwrite_f(dset, mem_type, buf, err)
      call h5dclose_f(dset, err2)
    end if
    call h5sclose_f(space, err2)
  end subroutine write_array

  !> Read every dataset of group `group` into st (cleared first): float
  !> datasets as real entries, integer ones as integer entries, strings as
  !> text. status names a missing group or a dataset that cannot be read.
  subroutine read_record(self, group, st, status)
    class(h5_record_file_t), intent(in) :: self
    character(len=*), intent(in) :: group
    type(state_record_t), intent(inout) :: st
    type(error_status_t), intent(inout) :: status
    integer(hid_t) :: g
    integer :: k, n, err, otype
    character(len=name_len) :: dname
    call st%clear()
    if (.not. self%has_group(group)) then
      call status%set("'"//trim(self%path)//"' has no group /"//group)
      return
    end if
    call h5gopen_f(self%id, group, g, err)
    if (err == 0) call h5gn_members_f(self%id, group, n, err)
    if (err /= 0) then
      call status%set("cannot read group /"//group//" of '"//trim(self%path)//"'")
      return
    end if
    do k = 0, n - 1
      call h5gget_obj_info_idx_f(self%id, group, k, dname, otype, err)
      if (err /= 0) exit
      if (otype /= H5G_DATASET_F) cycle
      call read_dataset(g, dname, st, err)
      if (err /= 0) exit
    end do
    if (err /= 0) call status%set("cannot read dataset /"//group//"/"//trim(dname)//" of '"//trim(self%path)//"'")
    call h5gclose_f(g, err)
  end subroutine read_record

  !> One 1-D dataset into the entry of the same name.
  subroutine read_dataset(g, name, st, err)
    integer(hid_t), intent(in) :: g
    character(len=*), intent(in) :: name
    type(state_record_t), intent(inout) :: st
    integer, intent(out) :: err
    integer(hid_t) :: dset, space, ft, mt
    integer(hsize_t) :: npts
    integer(size_t) :: tsize
    integer :: cls, err2, n
    real(rp), allocatable, target :: r(:)
    integer, allocatable, target :: iv(:)
    character(kind=c_char), allocatable, target :: text(:)
    character(len=name_len), allocatable :: names(:)
    type(c_ptr) :: p
    call h5dopen_f(g, trim(name), dset, err)
    if (err /= 0) return
    call h5dget_space_f(dset, space, err)
    call h5sget_simple_extent_npoints_f(space, npts, err2)
    call h5sclose_f(space, err2)
    call h5dget_type_f(dset, ft, err2)
    call h5tget_class_f(ft, cls, err2)
    call h5tget_size_f(ft, tsize, err2)
    call h5tclose_f(ft, err2)
    n = int(npts)
    ! (the class constants are variables of the HDF5 module: no select case)
    if (cls == H5T_FLOAT_F) then
      allocate(r(max(n, 1)))
      p = c_loc(r)
      if (n > 0) call h5dread_f(dset, h5kind_to_type(rp, H5_REAL_KIND), p, err)
      call st%put(name, r(1:n))
    else if (cls == H5T_INTEGER_F) then
      allocate(iv(max(n, 1)))
      p = c_loc(iv)
      if (n > 0) call h5dread_f(dset, h5kind_to_type(kind(iv), H5_INTEGER_KIND), p, err)
      call st%put(name, iv(1:n))
    else if (cls == H5T_STRING_F) then
      if (tsize /= int(name_len, size_t)) then
        err = 1
      else
        allocate(text(max(1, n * name_len)), names(n))
        call text_type(name_len, mt, err)
        p = c_loc(text)
        if (n > 0 .and. err == 0) call h5dread_f(dset, mt, p, err)
        call h5tclose_f(mt, err2)
        if (n > 0) names = transfer(text, names, n)
        call st%put(name, names)
      end if
    else
      err = 1
    end if
    call h5dclose_f(dset, err2)
  end subroutine read_dataset

  ! C addresses of record arrays (never used when the array is empty).
  function r_ptr(a) result(p)
    real(rp), intent(in), target :: a(:)
    type(c_ptr) :: p
    p = c_null_ptr
    if (size(a) > 0) p = c_loc(a(1))
  end function r_ptr

  function i_ptr(a) result(p)
    integer, intent(in), target :: a(:)
    type(c_ptr) :: p
    p = c_null_ptr
    if (size(a) > 0) p = c_loc(a(1))
  end function i_ptr
end module h5_record
