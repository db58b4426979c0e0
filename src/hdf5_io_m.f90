!> The only module that touches HDF5. Writes mfcd's output files (every dataset carries a
!! 'units' attribute; layout in doc/output.md) and reads particle files.
module hdf5_io_m
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5fcreate_f, h5fclose_f, h5fopen_f, &
    h5gcreate_f, h5gclose_f, h5screate_simple_f, h5screate_f, h5sclose_f, h5dcreate_f, &
    h5dwrite_f, h5dclose_f, h5dopen_f, h5dread_f, h5dget_space_f, &
    h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5acreate_f, h5awrite_f, &
    h5aclose_f, h5oopen_f, h5oclose_f, h5tcopy_f, h5tset_size_f, h5tclose_f, h5lexists_f, &
    H5F_ACC_EXCL_F, H5F_ACC_RDONLY_F, H5T_NATIVE_DOUBLE, H5T_NATIVE_INTEGER, &
    H5T_FORTRAN_S1, H5S_SCALAR_F, h5eset_auto_f, h5pcreate_f, h5pset_chunk_f, h5pclose_f, &
    H5P_DATASET_CREATE_F, H5S_UNLIMITED_F, h5dset_extent_f, h5sselect_hyperslab_f, &
    H5S_SELECT_SET_F, h5fflush_f, H5F_SCOPE_GLOBAL_F
  implicit none
  private
  public :: h5file_t, h5_create, h5_close, h5_group, h5_write, h5_attr, h5_text
  public :: read_particle_file_h5, h5_series_create, h5_series_append, h5_flush

  type :: h5file_t
    integer(hid_t) :: id = -1
    character(len=:), allocatable :: path
  end type h5file_t

  !> Dataset writers: real and integer arrays of rank 1 and 2, each with its units.
  interface h5_write
    module procedure write_r1, write_r2, write_i1, write_i2
  end interface h5_write

  !> Attributes on a group or dataset: text, real or integer scalars, real rank 1.
  interface h5_attr
    module procedure attr_str, attr_real, attr_int, attr_r1
  end interface h5_attr

contains

  !> Create a new HDF5 file. It fails when path exists (the HDF5 library opens it with
  !! O_EXCL): mfcd never truncates a file, it writes only names it has just created.
  subroutine h5_create(f, path, err)
    type(h5file_t), intent(out) :: f
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    integer :: st
    call h5open_f(st)
    if (st /= 0) then
      call set_error(err, 'HDF5 library failed to initialise', 1)
      return
    end if
    call h5eset_auto_f(0, st)
    call h5fcreate_f(path, H5F_ACC_EXCL_F, f%id, st)
    if (st /= 0) then
      call set_error(err, "output file '"//path//"' cannot be created (it exists, or its "// &
        "directory is not writable); check the directory of &output file", 1)
      return
    end if
    f%path = path
  end subroutine h5_create

  subroutine h5_close(f, err)
    type(h5file_t), intent(inout) :: f
    type(error_t), allocatable, intent(inout) :: err
    integer :: st
    if (f%id < 0) return
    call h5fclose_f(f%id, st)
    f%id = -1
    if (st /= 0) call set_error(err, "output file '"//f%path//"': close failed", 1)
  end subroutine h5_close

  !> Create a group (its parent must exist).
  subroutine h5_group(f, path, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: g
    integer :: st
    call h5gcreate_f(f%id, path, g, st)
    if (st == 0) call h5gclose_f(g, st)
    if (st /= 0) call fail(f, path, 'group create', err)
  end subroutine h5_group

  subroutine fail(f, path, what, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, what
    type(error_t), allocatable, intent(inout) :: err
    call set_error(err, "output file '"//f%path//"': HDF5 "//what//" failed for "//path, 1)
  end subroutine fail

  subroutine finish_dataset(f, path, dset, space, units, descr, st, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    character(len=*), intent(in), optional :: descr
    integer(hid_t), intent(in) :: dset, space
    integer, intent(in) :: st
    type(error_t), allocatable, intent(inout) :: err
    integer :: s2
    call h5dclose_f(dset, s2)
    call h5sclose_f(space, s2)
    if (st /= 0) then
      call fail(f, path, 'write', err)
      return
    end if
    call attr_str(f, path, 'units', units, err)
    if (present(descr) .and. .not. allocated(err)) call attr_str(f, path, 'description', &
      descr, err)
  end subroutine finish_dataset

  subroutine write_r1(f, path, a, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    real(wp), intent(in) :: a(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(1)
    integer :: st
    dims = shape(a, kind=hsize_t)
    call h5screate_simple_f(1, dims, space, st)
    call h5dcreate_f(f%id, path, H5T_NATIVE_DOUBLE, space, dset, st)
    if (st == 0) call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, a, dims, st)
    call finish_dataset(f, path, dset, space, units, descr, st, err)
  end subroutine write_r1

  subroutine write_r2(f, path, a, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    real(wp), intent(in) :: a(:, :)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(2)
    integer :: st
    dims = shape(a, kind=hsize_t)
    call h5screate_simple_f(2, dims, space, st)
    call h5dcreate_f(f%id, path, H5T_NATIVE_DOUBLE, space, dset, st)
    if (st == 0) call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, a, dims, st)
    call finish_dataset(f, path, dset, space, units, descr, st, err)
  end subroutine write_r2

  subroutine write_i1(f, path, a, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    integer, intent(in) :: a(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(1)
    integer :: st
    dims = shape(a, kind=hsize_t)
    call h5screate_simple_f(1, dims, space, st)
    call h5dcreate_f(f%id, path, H5T_NATIVE_INTEGER, space, dset, st)
    if (st == 0) call h5dwrite_f(dset, H5T_NATIVE_INTEGER, a, dims, st)
    call finish_dataset(f, path, dset, space, units, descr, st, err)
  end subroutine write_i1

  subroutine write_i2(f, path, a, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    integer, intent(in) :: a(:, :)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(2)
    integer :: st
    dims = shape(a, kind=hsize_t)
    call h5screate_simple_f(2, dims, space, st)
    call h5dcreate_f(f%id, path, H5T_NATIVE_INTEGER, space, dset, st)
    if (st == 0) call h5dwrite_f(dset, H5T_NATIVE_INTEGER, a, dims, st)
    call finish_dataset(f, path, dset, space, units, descr, st, err)
  end subroutine write_i2

  !> An extendible 1D real dataset (a time series), empty at creation.
  subroutine h5_series_create(f, path, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    integer(hid_t) :: space, dset, plist
    integer(hsize_t) :: dims(1), maxdims(1), chunk(1)
    integer :: st, s2
    dims = 0
    maxdims = H5S_UNLIMITED_F
    chunk = 1024
    call h5screate_simple_f(1, dims, space, st, maxdims)
    call h5pcreate_f(H5P_DATASET_CREATE_F, plist, st)
    call h5pset_chunk_f(plist, 1, chunk, st)
    call h5dcreate_f(f%id, path, H5T_NATIVE_DOUBLE, space, dset, st, plist)
    call h5pclose_f(plist, s2)
    call finish_dataset(f, path, dset, space, units, descr, st, err)
  end subroutine h5_series_create

  !> Append values to an extendible 1D dataset made by h5_series_create.
  subroutine h5_series_append(f, path, values, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: values(:)
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: dset, fspace, mspace
    integer(hsize_t) :: dims(1), maxdims(1), newdims(1), offset(1), count(1)
    integer :: st, s2
    if (size(values) == 0) return
    call h5dopen_f(f%id, path, dset, st)
    if (st /= 0) then
      call fail(f, path, 'open', err)
      return
    end if
    call h5dget_space_f(dset, fspace, st)
    call h5sget_simple_extent_dims_f(fspace, dims, maxdims, st)
    call h5sclose_f(fspace, s2)
    newdims = dims + size(values, kind=hsize_t)
    call h5dset_extent_f(dset, newdims, st)
    call h5dget_space_f(dset, fspace, st)
    offset = dims
    count = size(values, kind=hsize_t)
    call h5sselect_hyperslab_f(fspace, H5S_SELECT_SET_F, offset, count, st)
    call h5screate_simple_f(1, count, mspace, st)
    call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, values, count, st, mspace, fspace)
    call h5sclose_f(mspace, s2)
    call h5sclose_f(fspace, s2)
    call h5dclose_f(dset, s2)
    if (st /= 0) call fail(f, path, 'append', err)
  end subroutine h5_series_append

  !> Push everything written so far to disk (a later crash keeps it).
  subroutine h5_flush(f)
    type(h5file_t), intent(in) :: f
    integer :: st
    call h5fflush_f(f%id, H5F_SCOPE_GLOBAL_F, st)
  end subroutine h5_flush

  !> A text dataset (e.g. the deck verbatim).
  subroutine h5_text(f, path, text, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, text
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: space, dset, t
    integer(hsize_t) :: dims(1)
    integer :: st
    dims = 1
    call h5tcopy_f(H5T_FORTRAN_S1, t, st)
    call h5tset_size_f(t, int(max(len(text), 1), size_t), st)
    call h5screate_f(H5S_SCALAR_F, space, st)
    call h5dcreate_f(f%id, path, t, space, dset, st)
    if (st == 0) call h5dwrite_f(dset, t, text, dims, st)
    call h5tclose_f(t, st)
    call finish_dataset(f, path, dset, space, 'text', st=st, err=err)
  end subroutine h5_text

  subroutine open_obj(f, path, obj, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer(hid_t), intent(out) :: obj
    type(error_t), allocatable, intent(inout) :: err
    integer :: st
    call h5oopen_f(f%id, path, obj, st)
    if (st /= 0) call fail(f, path, 'open', err)
  end subroutine open_obj

  subroutine attr_str(f, path, name, val, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name, val
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: obj, space, a, t
    integer(hsize_t) :: dims(1)
    integer :: st, s2
    call open_obj(f, path, obj, err)
    if (allocated(err)) return
    dims = 1
    call h5tcopy_f(H5T_FORTRAN_S1, t, st)
    call h5tset_size_f(t, int(max(len(val), 1), size_t), st)
    call h5screate_f(H5S_SCALAR_F, space, st)
    call h5acreate_f(obj, name, t, space, a, st)
    ! an empty text is stored as one blank (HDF5 strings have at least one character)
    if (st == 0) call h5awrite_f(a, t, val//repeat(' ', merge(1, 0, len(val) == 0)), dims, st)
    call h5aclose_f(a, s2)
    call h5sclose_f(space, s2)
    call h5tclose_f(t, s2)
    call h5oclose_f(obj, s2)
    if (st /= 0) call fail(f, path//'@'//name, 'attribute write', err)
  end subroutine attr_str

  subroutine attr_real(f, path, name, val, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name
    real(wp), intent(in) :: val
    type(error_t), allocatable, intent(inout) :: err
    call attr_r1(f, path, name, [val], err)
  end subroutine attr_real

  subroutine attr_r1(f, path, name, val, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name
    real(wp), intent(in) :: val(:)
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: obj, space, a
    integer(hsize_t) :: dims(1)
    integer :: st, s2
    call open_obj(f, path, obj, err)
    if (allocated(err)) return
    dims = size(val)
    call h5screate_simple_f(1, dims, space, st)
    call h5acreate_f(obj, name, H5T_NATIVE_DOUBLE, space, a, st)
    if (st == 0) call h5awrite_f(a, H5T_NATIVE_DOUBLE, val, dims, st)
    call h5aclose_f(a, s2)
    call h5sclose_f(space, s2)
    call h5oclose_f(obj, s2)
    if (st /= 0) call fail(f, path//'@'//name, 'attribute write', err)
  end subroutine attr_r1

  subroutine attr_int(f, path, name, val, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name
    integer, intent(in) :: val
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: obj, space, a
    integer(hsize_t) :: dims(1)
    integer :: st, s2
    call open_obj(f, path, obj, err)
    if (allocated(err)) return
    dims = 1
    call h5screate_f(H5S_SCALAR_F, space, st)
    call h5acreate_f(obj, name, H5T_NATIVE_INTEGER, space, a, st)
    if (st == 0) call h5awrite_f(a, H5T_NATIVE_INTEGER, val, dims, st)
    call h5aclose_f(a, s2)
    call h5sclose_f(space, s2)
    call h5oclose_f(obj, s2)
    if (st /= 0) call fail(f, path//'@'//name, 'attribute write', err)
  end subroutine attr_int

  !> Read a particle file: /particles/x (ndim, np in Fortran order; (np, ndim) in h5py),
  !! /particles/volume (np) and optional /particles/loop, /particles/order (np, integers).
  subroutine read_particle_file_h5(path, ndim, x, vol, loop, order, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ndim
    real(wp), allocatable, intent(out) :: x(:, :), vol(:)
    integer, allocatable, intent(out) :: loop(:), order(:)
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: fid
    integer(hsize_t) :: dims(2)
    integer :: st, rank, np
    logical :: exists
    call h5open_f(st)
    call h5eset_auto_f(0, st)
    call h5fopen_f(path, H5F_ACC_RDONLY_F, fid, st)
    if (st /= 0) then
      call set_error(err, "particle file '"//path//"' is not a readable HDF5 file")
      return
    end if
    call dims_of(fid, '/particles/x', rank, dims, st)
    if (st /= 0 .or. rank /= 2) then
      call set_error(err, "particle file '"//path//"': dataset /particles/x (np x ndim) missing")
    else if (int(dims(1)) /= ndim) then
      call set_error(err, "particle file '"//path//"': /particles/x has the wrong number "// &
        "of coordinates for &run ndim")
    end if
    if (allocated(err)) then
      call h5fclose_f(fid, st)
      return
    end if
    np = int(dims(2))
    allocate(x(ndim, np), vol(np), loop(np), order(np))
    call read_real(fid, '/particles/x', x, [int(ndim, hsize_t), int(np, hsize_t)], st)
    if (st == 0) call read_real1(fid, '/particles/volume', vol, st)
    if (st /= 0) then
      call set_error(err, "particle file '"//path//"': cannot read /particles/x and "// &
        "/particles/volume (np values)")
      call h5fclose_f(fid, st)
      return
    end if
    loop = 0
    order = 0
    call h5lexists_f(fid, 'particles/loop', exists, st)
    if (exists .and. st == 0) then
      call read_int(fid, '/particles/loop', loop, int(np, hsize_t), st)
      if (st == 0) call read_int(fid, '/particles/order', order, int(np, hsize_t), st)
      if (st /= 0) call set_error(err, "particle file '"//path// &
        "': /particles/loop given but /particles/order missing or of the wrong size")
    end if
    call h5fclose_f(fid, st)
  end subroutine read_particle_file_h5

  subroutine dims_of(fid, path, rank, dims, st)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer, intent(out) :: rank, st
    integer(hsize_t), intent(out) :: dims(2)
    integer(hid_t) :: d, sp
    integer(hsize_t) :: mx(2)
    integer :: s2
    rank = 0
    dims = 0
    call h5dopen_f(fid, path, d, st)
    if (st /= 0) return
    call h5dget_space_f(d, sp, st)
    call h5sget_simple_extent_ndims_f(sp, rank, st)
    if (rank == 2) call h5sget_simple_extent_dims_f(sp, dims, mx, st)
    if (st > 0) st = 0
    call h5sclose_f(sp, s2)
    call h5dclose_f(d, s2)
  end subroutine dims_of

  subroutine read_real(fid, path, buf, dims, st)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    real(wp), intent(inout) :: buf(:, :)
    integer(hsize_t), intent(in) :: dims(2)
    integer, intent(out) :: st
    integer(hid_t) :: d
    integer :: s2
    call h5dopen_f(fid, path, d, st)
    if (st /= 0) return
    call h5dread_f(d, H5T_NATIVE_DOUBLE, buf, dims, st)
    call h5dclose_f(d, s2)
  end subroutine read_real

  subroutine read_real1(fid, path, buf, st)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    real(wp), intent(inout) :: buf(:)
    integer, intent(out) :: st
    integer(hid_t) :: d
    integer(hsize_t) :: dims(1)
    integer :: s2
    dims = size(buf, kind=hsize_t)
    call h5dopen_f(fid, path, d, st)
    if (st /= 0) return
    call h5dread_f(d, H5T_NATIVE_DOUBLE, buf, dims, st)
    call h5dclose_f(d, s2)
  end subroutine read_real1

  subroutine read_int(fid, path, buf, n, st)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer, intent(inout) :: buf(:)
    integer(hsize_t), intent(in) :: n
    integer, intent(out) :: st
    integer(hid_t) :: d
    integer(hsize_t) :: dims(1)
    integer :: s2
    dims = n
    call h5dopen_f(fid, path, d, st)
    if (st /= 0) return
    call h5dread_f(d, H5T_NATIVE_INTEGER, buf, dims, st)
    call h5dclose_f(d, s2)
  end subroutine read_int
end module hdf5_io_m
