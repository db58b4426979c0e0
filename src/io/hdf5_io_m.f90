!> The only module that touches HDF5. Writes mfcd's output files (every dataset carries a
!! 'units' attribute; layout in doc/output.md), reads particle files, and reads back what
!! it wrote (checkpoints, doc/output.md) with every shape checked.
module hdf5_io_m
  use, intrinsic :: iso_c_binding, only: c_loc, c_ptr
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5fcreate_f, h5fclose_f, h5fopen_f, &
    h5gcreate_f, h5gclose_f, h5screate_simple_f, h5screate_f, h5sclose_f, h5dcreate_f, &
    h5dwrite_f, h5dclose_f, h5dopen_f, h5dread_f, h5dget_space_f, &
    h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5acreate_f, h5awrite_f, &
    h5aclose_f, h5oopen_f, h5oclose_f, h5tcopy_f, h5tset_size_f, h5tclose_f, h5lexists_f, &
    H5F_ACC_EXCL_F, H5F_ACC_RDONLY_F, H5T_NATIVE_DOUBLE, H5T_NATIVE_INTEGER, &
    H5T_FORTRAN_S1, H5S_SCALAR_F, h5eset_auto_f, h5pcreate_f, h5pset_chunk_f, h5pclose_f, &
    H5P_DATASET_CREATE_F, H5S_UNLIMITED_F, h5dset_extent_f, h5sselect_hyperslab_f, &
    H5S_SELECT_SET_F, h5fflush_f, H5F_SCOPE_GLOBAL_F, h5fis_hdf5_f, h5aopen_f, h5aread_f, &
    h5aexists_f, h5aget_type_f, h5aget_space_f, h5dget_type_f, h5tget_size_f, &
    h5kind_to_type, H5_INTEGER_KIND, H5F_ACC_RDWR_F, H5P_DEFAULT_F, H5S_SELECT_OR_F, &
    h5sselect_none_f, h5pset_obj_track_times_f, H5P_FILE_CREATE_F, H5P_GROUP_CREATE_F, &
    h5sselect_elements_f
  implicit none
  private
  public :: h5file_t, h5_create, h5_close, h5_group, h5_write, h5_attr, h5_text
  public :: read_particle_file_h5, h5_series_create, h5_series_append, h5_flush
  public :: h5_open_read, h5_has, h5_has_attr, h5_shape, h5_read, h5_read_attr, h5_read_text
  public :: h5_open_rw, h5_write_rows, h5_read_rows, h5_read_block

  type :: h5file_t
    integer(hid_t) :: id = -1
    character(len=:), allocatable :: path
    !> the data transfer property list of h5_write_rows (-1: the default; a file opened on
    !! MPI ranks sets a collective one, mpi_output_m)
    integer(hid_t) :: xfer = -1
  end type h5file_t

  !> Rows of a dataset of n rows written by their global numbers (h5_write_rows): each rank
  !! of a file opened with MPI-IO writes its own rows, collectively, into one dataset whose
  !! layout is a serial run's (rows in global order).
  interface h5_write_rows
    module procedure rows_r1, rows_r2, rows_i1, rows_i2
  end interface h5_write_rows

  !> Dataset writers: real and integer arrays of rank 1 and 2, each with its units.
  interface h5_write
    module procedure write_r1, write_r2, write_i1, write_i2, write_i64
  end interface h5_write

  !> Dataset readers into arrays of the caller's shape: the stored shape must match it.
  interface h5_read
    module procedure read_ds_r1, read_ds_r2, read_ds_i64, read_ds_i64_2
  end interface h5_read

  !> Rows first ... first + size(a, rank) - 1 of a dataset of rank 1 or 2 (a block of its
  !! last dimension, the rows h5py shows first), the other dimension checked against a's:
  !! what a rank streams of a mesh file it reads per part (tet_file_m).
  interface h5_read_block
    module procedure block_r1, block_r2, block_i64_2, block_i1
  end interface h5_read_block

  !> Attribute readers: text (any length), integer scalar, real rank 1 of the caller's size.
  interface h5_read_attr
    module procedure read_attr_str, read_attr_int, read_attr_real, read_attr_r1
  end interface h5_read_attr

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
    integer :: st, s2
    integer(hid_t) :: fcpl
    call h5open_f(st)
    if (st /= 0) then
      call set_error(err, 'HDF5 library failed to initialise', 1)
      return
    end if
    call h5eset_auto_f(0, st)
    ! (the root group's header without times either: the file's bytes are what is written)
    call h5pcreate_f(H5P_FILE_CREATE_F, fcpl, st)
    if (st == 0) call h5pset_obj_track_times_f(fcpl, .false., st)
    if (st == 0) call h5fcreate_f(path, H5F_ACC_EXCL_F, f%id, st, creation_prp=fcpl)
    call h5pclose_f(fcpl, s2)
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
    integer(hid_t) :: g, gcpl
    integer :: st, s2
    call h5pcreate_f(H5P_GROUP_CREATE_F, gcpl, st)
    if (st == 0) call h5pset_obj_track_times_f(gcpl, .false., st)
    if (st == 0) call h5gcreate_f(f%id, path, g, st, gcpl_id=gcpl)
    call h5pclose_f(gcpl, s2)
    if (st == 0) call h5gclose_f(g, st)
    if (st /= 0) call fail(f, path, 'group create', err)
  end subroutine h5_group

  !> Dataset path of type t on dataspace space, with chunk its chunk shape (else
  !! contiguous), created without access, modification and change times in its header
  !! (HDF5 records them by default): the file's bytes are then a function of what is
  !! written, not of when, the same from runs on any number of ranks.
  subroutine dcreate(f, path, t, space, dset, st, chunk)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer(hid_t), intent(in) :: t, space
    integer(hid_t), intent(out) :: dset
    integer, intent(out) :: st
    integer(hsize_t), intent(in), optional :: chunk(:)
    integer(hid_t) :: dcpl
    integer :: s2
    dset = -1
    call h5pcreate_f(H5P_DATASET_CREATE_F, dcpl, st)
    if (st /= 0) return
    call h5pset_obj_track_times_f(dcpl, .false., st)
    if (present(chunk) .and. st == 0) call h5pset_chunk_f(dcpl, size(chunk), chunk, st)
    if (st == 0) call h5dcreate_f(f%id, path, t, space, dset, st, dcpl)
    call h5pclose_f(dcpl, s2)
  end subroutine dcreate

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
    call dcreate(f, path, H5T_NATIVE_DOUBLE, space, dset, st)
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
    call dcreate(f, path, H5T_NATIVE_DOUBLE, space, dset, st)
    if (st == 0) call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, a, dims, st)
    call finish_dataset(f, path, dset, space, units, descr, st, err)
  end subroutine write_r2

  !> a(i) into row gid(i) of the new dataset path (n), gid ascending; see rows_r2.
  subroutine rows_r1(f, path, a, gid, n, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    real(wp), intent(in), target, contiguous :: a(:)
    integer, intent(in) :: gid(:), n
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    call rows_write(f, path, 1, 1, c_loc(a), H5T_NATIVE_DOUBLE, gid, n, units, err, descr)
  end subroutine rows_r1

  !> a(:, i) into column gid(i) of the new dataset path (size(a, 1), n), gid ascending: in
  !! a serial file with gid = 1..n the same dataset as h5_write; in a file opened with
  !! MPI-IO every rank calls it with its own rows (none is fine), collectively.
  subroutine rows_r2(f, path, a, gid, n, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    real(wp), intent(in), target, contiguous :: a(:, :)
    integer, intent(in) :: gid(:), n
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    call rows_write(f, path, 2, size(a, 1), c_loc(a), H5T_NATIVE_DOUBLE, gid, n, units, &
      err, descr)
  end subroutine rows_r2

  !> Integer rows (rows_r1): the dataset h5_write makes of an integer vector.
  subroutine rows_i1(f, path, a, gid, n, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    integer, intent(in), target, contiguous :: a(:)
    integer, intent(in) :: gid(:), n
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    call rows_write(f, path, 1, 1, c_loc(a), H5T_NATIVE_INTEGER, gid, n, units, err, descr)
  end subroutine rows_i1

  !> Integer columns (rows_r2): the dataset h5_write makes of an integer matrix.
  subroutine rows_i2(f, path, a, gid, n, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    integer, intent(in), target, contiguous :: a(:, :)
    integer, intent(in) :: gid(:), n
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    call rows_write(f, path, 2, size(a, 1), c_loc(a), H5T_NATIVE_INTEGER, gid, n, units, &
      err, descr)
  end subroutine rows_i2

  !> rows_r1, rows_i1 (rk = 1, m = 1) and rows_r2, rows_i2 (rk = 2): the m x size(gid)
  !! values at buf (of memory type mtype, column after column) fill the file's selection,
  !! the runs of consecutive numbers in gid, in the file's order.
  subroutine rows_write(f, path, rk, m, buf, mtype, gid, n, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    integer, intent(in) :: rk, m, gid(:), n
    type(c_ptr), intent(in) :: buf
    integer(hid_t), intent(in) :: mtype
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    integer(hid_t) :: space, dset, mspace, xfer
    integer(hsize_t) :: dims(2), mdims(2)
    integer :: st, s2
    real(wp), target :: none(1)
    if (any(gid(2:) <= gid(:size(gid) - 1)) .or. any(gid < 1 .or. gid > n)) then
      call set_error(err, "output file '"//f%path//"': rows of "//path//" not in order "// &
        "(an internal error)", 1)
      return
    end if
    dims = [int(m, hsize_t), int(n, hsize_t)]
    mdims = [int(m, hsize_t), max(1_hsize_t, size(gid, kind=hsize_t))]
    if (rk == 1) then
      dims(1) = dims(2)
      mdims(1) = mdims(2)
    end if
    none = 0.0_wp
    xfer = H5P_DEFAULT_F
    if (f%xfer >= 0) xfer = f%xfer
    call h5screate_simple_f(rk, dims, space, st)
    call dcreate(f, path, mtype, space, dset, st)
    if (st /= 0) then
      call finish_dataset(f, path, dset, space, units, descr, st, err)
      return
    end if
    call h5screate_simple_f(rk, mdims, mspace, st)
    call select_rows(space, mspace, rk, m, gid, st)
    if (st == 0 .and. size(gid) > 0) then
      call h5dwrite_f(dset, mtype, buf, st, mspace, space, xfer)
    else if (st == 0) then
      ! no rows here: the collective write still takes part, with nothing selected
      call h5dwrite_f(dset, mtype, c_loc(none), st, mspace, space, xfer)
    end if
    call h5sclose_f(mspace, s2)
    call finish_dataset(f, path, dset, space, units, descr, st, err)
  end subroutine rows_write

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
    call dcreate(f, path, H5T_NATIVE_INTEGER, space, dset, st)
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
    call dcreate(f, path, H5T_NATIVE_INTEGER, space, dset, st)
    if (st == 0) call h5dwrite_f(dset, H5T_NATIVE_INTEGER, a, dims, st)
    call finish_dataset(f, path, dset, space, units, descr, st, err)
  end subroutine write_i2

  !> A 64-bit integer vector (counters that can exceed 2**31).
  subroutine write_i64(f, path, a, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    integer(i64), intent(in) :: a(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    integer(i64), allocatable, target :: buf(:)
    integer(hid_t) :: space, dset, t
    integer(hsize_t) :: dims(1)
    integer :: st
    allocate(buf, source=a)
    t = h5kind_to_type(i64, H5_INTEGER_KIND)
    dims = shape(a, kind=hsize_t)
    call h5screate_simple_f(1, dims, space, st)
    call dcreate(f, path, t, space, dset, st)
    if (st == 0) call h5dwrite_f(dset, t, c_loc(buf), st)
    call finish_dataset(f, path, dset, space, units, descr, st, err)
  end subroutine write_i64

  !> An extendible 1D real dataset (a time series), empty at creation.
  subroutine h5_series_create(f, path, units, err, descr)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, units
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: descr
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(1), maxdims(1), chunk(1)
    integer :: st
    dims = 0
    maxdims = H5S_UNLIMITED_F
    chunk = 1024
    call h5screate_simple_f(1, dims, space, st, maxdims)
    call dcreate(f, path, H5T_NATIVE_DOUBLE, space, dset, st, chunk)
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
    call dcreate(f, path, t, space, dset, st)
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
  !> Open an existing HDF5 file read-only (the reader's half of this module: checkpoints).
  !! err (exit 2) when path is missing, not an HDF5 file, or cannot be opened.
  subroutine h5_open_read(f, path, err)
    type(h5file_t), intent(out) :: f
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    logical :: exists, is_h5
    integer :: st
    inquire(file=path, exist=exists)
    if (.not. exists) then
      call set_error(err, "file '"//path//"' not found")
      return
    end if
    call h5open_f(st)
    call h5eset_auto_f(0, st)
    call h5fis_hdf5_f(path, is_h5, st)
    if (st /= 0 .or. .not. is_h5) then
      call set_error(err, "'"//path//"' is not an HDF5 file")
      return
    end if
    call h5fopen_f(path, H5F_ACC_RDONLY_F, f%id, st)
    if (st /= 0) then
      f%id = -1
      call set_error(err, "HDF5 file '"//path//"' cannot be opened for reading")
      return
    end if
    f%path = path
  end subroutine h5_open_read

  !> The file space's selection of the rows gid (ascending) of a dataset of rank rk with m
  !! values a row, and none of either space when gid is empty. A few runs of consecutive
  !! numbers (a lattice's part) are hyperslabs joined with H5S_SELECT_OR; more, the rows
  !! as points, in the memory buffer's order (component fastest). HDF5 joins each
  !! hyperslab to the selection so far by walking it, so k runs cost k^2: a gmsh mesh's
  !! part has its rows scattered over the whole numbering (a tetrahedron a run), and one
  !! snapshot of the 193,438 tetrahedra of a Taylor bar on 2 ranks took 270 s that way.
  subroutine select_rows(space, mspace, rk, m, gid, st)
    integer(hid_t), intent(in) :: space, mspace
    integer, intent(in) :: rk, m, gid(:)
    integer, intent(out) :: st
    !> the most runs joined as hyperslabs (a part of a lattice body has a few per plane)
    integer, parameter :: max_runs = 256
    integer(hsize_t) :: start(2), cnt(2)
    integer(hsize_t), allocatable :: coord(:, :)
    integer :: i, j, op, s2, nrun, c
    st = 0
    if (size(gid) == 0) then
      call h5sselect_none_f(space, st)
      call h5sselect_none_f(mspace, s2)
      return
    end if
    nrun = 1 + count(gid(2:) /= gid(:size(gid) - 1) + 1)
    if (nrun > max_runs) then
      ! (the points in the order of the memory buffer a(m, size(gid)); 1-based)
      allocate(coord(rk, m*size(gid)))
      do i = 1, size(gid)
        do c = 1, m
          if (rk == 1) then
            coord(1, i) = int(gid(i), hsize_t)
          else
            coord(:, m*(i - 1) + c) = [int(c, hsize_t), int(gid(i), hsize_t)]
          end if
        end do
      end do
      call h5sselect_elements_f(space, H5S_SELECT_SET_F, rk, size(coord, 2, kind=size_t), &
        coord, st)
      return
    end if
    op = H5S_SELECT_SET_F
    i = 1
    do while (i <= size(gid))
      j = i
      do while (j < size(gid))
        if (gid(j + 1) /= gid(j) + 1) exit
        j = j + 1
      end do
      start = [0_hsize_t, int(gid(i) - 1, hsize_t)]
      cnt = [int(m, hsize_t), int(j - i + 1, hsize_t)]
      if (rk == 1) then
        start(1) = start(2)
        cnt(1) = cnt(2)
      end if
      call h5sselect_hyperslab_f(space, op, start(:rk), cnt(:rk), st)
      if (st /= 0) return
      op = H5S_SELECT_OR_F
      i = j + 1
    end do
  end subroutine select_rows

  !> Rows gid (ascending) of the dataset path of n rows into a(:, i) (a dataset of rank 1
  !! when m = size(a, 1) = 1 and one1), the stored shape checked: what a rank reads of a
  !! checkpoint, its own and ghost rows only.
  subroutine h5_read_rows(f, path, a, gid, n, one1, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    real(wp), intent(inout) :: a(:, :)
    integer, intent(in) :: gid(:), n
    logical, intent(in) :: one1
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: d, space, mspace
    integer(hsize_t) :: mdims(2)
    integer :: st, s2, rk, m
    m = size(a, 1)
    rk = merge(1, 2, one1)
    if (any(gid(2:) <= gid(:size(gid) - 1)) .or. any(gid < 1 .or. gid > n) .or. &
      size(a, 2) /= size(gid) .or. (one1 .and. m /= 1)) then
      call read_fail(f, path, 'rows asked out of order (an internal error)', err)
      return
    end if
    if (one1) then
      call open_checked(f, path, [n], d, err)
    else
      call open_checked(f, path, [m, n], d, err)
    end if
    if (allocated(err) .or. size(gid) == 0) then
      if (d >= 0) call h5dclose_f(d, s2)
      return
    end if
    mdims = [int(m, hsize_t), size(gid, kind=hsize_t)]
    if (one1) mdims(1) = mdims(2)
    call h5dget_space_f(d, space, st)
    call h5screate_simple_f(rk, mdims(:rk), mspace, st)
    call select_rows(space, mspace, rk, m, gid, st)
    if (st == 0) call h5dread_f(d, H5T_NATIVE_DOUBLE, a, mdims(:rk), st, mspace, space)
    call h5sclose_f(mspace, s2)
    call h5sclose_f(space, s2)
    call h5dclose_f(d, s2)
    if (st /= 0) call read_fail(f, path, 'rows cannot be read', err)
  end subroutine h5_read_rows

  !> Open dataset path of rank rk whose leading extent (rank 2) is m, with rows first ...
  !! first + n - 1 in it; the file space selects them, the memory space holds them (d < 0:
  !! err set).
  subroutine block_open(f, path, rk, m, first, n, d, space, mspace, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer, intent(in) :: rk, m, first, n
    integer(hid_t), intent(out) :: d, space, mspace
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: dims(:)
    integer(hsize_t) :: start(2), cnt(2)
    integer :: st
    d = -1
    call h5_shape(f, path, dims, err)
    if (allocated(err)) return
    if (size(dims) /= rk) then
      call read_fail(f, path, 'rank '//itoa(size(dims))//' where '//itoa(rk)// &
        ' is expected', err)
      return
    end if
    if (rk == 2) then
      if (dims(1) /= m) then
        call read_fail(f, path, itoa(dims(1))//' values a row where '//itoa(m)// &
          ' are expected', err)
        return
      end if
    end if
    if (first < 1 .or. n < 0 .or. first + n - 1 > dims(rk)) then
      call read_fail(f, path, 'rows '//itoa(first)//' ... '//itoa(first + n - 1)// &
        ' asked of '//itoa(dims(rk))//' (an internal error)', err)
      return
    end if
    call h5dopen_f(f%id, path, d, st)
    if (st /= 0) then
      d = -1
      call read_fail(f, path, 'cannot be opened', err)
      return
    end if
    start = [0_hsize_t, int(first - 1, hsize_t)]
    cnt = [int(m, hsize_t), int(n, hsize_t)]
    if (rk == 1) then
      start(1) = start(2)
      cnt(1) = cnt(2)
    end if
    call h5dget_space_f(d, space, st)
    call h5sselect_hyperslab_f(space, H5S_SELECT_SET_F, start(:rk), cnt(:rk), st)
    call h5screate_simple_f(rk, cnt(:rk), mspace, st)
  end subroutine block_open

  subroutine block_close(f, path, d, space, mspace, st, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer(hid_t), intent(in) :: d, space, mspace
    integer, intent(in) :: st
    type(error_t), allocatable, intent(inout) :: err
    integer :: s2
    call h5sclose_f(mspace, s2)
    call h5sclose_f(space, s2)
    call h5dclose_f(d, s2)
    if (st /= 0) call read_fail(f, path, 'rows cannot be read', err)
  end subroutine block_close

  subroutine block_r1(f, path, a, first, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    real(wp), intent(inout) :: a(:)
    integer, intent(in) :: first
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: d, space, mspace
    integer :: st
    call block_open(f, path, 1, 1, first, size(a), d, space, mspace, err)
    if (d < 0) return
    st = 0
    if (size(a) > 0) call h5dread_f(d, H5T_NATIVE_DOUBLE, a, shape(a, kind=hsize_t), st, &
      mspace, space)
    call block_close(f, path, d, space, mspace, st, err)
  end subroutine block_r1

  subroutine block_r2(f, path, a, first, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    real(wp), intent(inout) :: a(:, :)
    integer, intent(in) :: first
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: d, space, mspace
    integer :: st
    call block_open(f, path, 2, size(a, 1), first, size(a, 2), d, space, mspace, err)
    if (d < 0) return
    st = 0
    if (size(a) > 0) call h5dread_f(d, H5T_NATIVE_DOUBLE, a, shape(a, kind=hsize_t), st, &
      mspace, space)
    call block_close(f, path, d, space, mspace, st, err)
  end subroutine block_r2

  !> (an integer column, as default integers: a plane mesh file's loop and order)
  subroutine block_i1(f, path, a, first, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer, intent(inout) :: a(:)
    integer, intent(in) :: first
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: d, space, mspace
    integer :: st
    call block_open(f, path, 1, 1, first, size(a), d, space, mspace, err)
    if (d < 0) return
    st = 0
    if (size(a) > 0) call h5dread_f(d, H5T_NATIVE_INTEGER, a, shape(a, kind=hsize_t), st, &
      mspace, space)
    call block_close(f, path, d, space, mspace, st, err)
  end subroutine block_i1

  subroutine block_i64_2(f, path, a, first, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer(i64), intent(inout) :: a(:, :)
    integer, intent(in) :: first
    type(error_t), allocatable, intent(inout) :: err
    integer(i64), allocatable, target :: buf(:, :)
    type(c_ptr) :: ptr
    integer(hid_t) :: d, space, mspace
    integer :: st
    call block_open(f, path, 2, size(a, 1), first, size(a, 2), d, space, mspace, err)
    if (d < 0) return
    st = 0
    allocate(buf(size(a, 1), size(a, 2)))
    ptr = c_loc(buf)
    if (size(a) > 0) call h5dread_f(d, h5kind_to_type(i64, H5_INTEGER_KIND), ptr, st, &
      mspace, space)
    call block_close(f, path, d, space, mspace, st, err)
    if (st == 0) a = buf
  end subroutine block_i64_2

  !> Open an existing HDF5 file of this run for writing (a run's file reopened after its
  !! snapshot was written collectively; with fapl, on every rank with MPI-IO).
  subroutine h5_open_rw(f, path, err, fapl)
    type(h5file_t), intent(out) :: f
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t), intent(in), optional :: fapl
    integer :: st
    call h5open_f(st)
    call h5eset_auto_f(0, st)
    if (present(fapl)) then
      call h5fopen_f(path, H5F_ACC_RDWR_F, f%id, st, fapl)
    else
      call h5fopen_f(path, H5F_ACC_RDWR_F, f%id, st)
    end if
    if (st /= 0) then
      f%id = -1
      call set_error(err, "output file '"//path//"' cannot be opened for writing", 1)
      return
    end if
    f%path = path
  end subroutine h5_open_rw

  !> Whether the object path ('/a/b/c') exists, every group on the way included.
  logical function h5_has(f, path) result(yes)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer :: k, j, st
    yes = .false.
    k = 1
    do
      j = index(path(k + 1:), '/')
      if (j == 0) exit
      call h5lexists_f(f%id, path(1:k + j - 1), yes, st)
      if (st /= 0 .or. .not. yes) then
        yes = .false.
        return
      end if
      k = k + j
    end do
    call h5lexists_f(f%id, path, yes, st)
    if (st /= 0) yes = .false.
  end function h5_has

  !> Whether object path exists and has the attribute name.
  logical function h5_has_attr(f, path, name) result(yes)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name
    integer(hid_t) :: obj
    integer :: st, s2
    yes = .false.
    if (path /= '/') then
      if (.not. h5_has(f, path)) return
    end if
    call h5oopen_f(f%id, path, obj, st)
    if (st /= 0) return
    call h5aexists_f(obj, name, yes, st)
    if (st /= 0) yes = .false.
    call h5oclose_f(obj, s2)
  end function h5_has_attr

  !> The shape of dataset path as Fortran wrote it (h5py shows it reversed).
  subroutine h5_shape(f, path, dims, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer, allocatable, intent(out) :: dims(:)
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: d, sp
    integer(hsize_t) :: hd(7), mx(7)
    integer :: st, s2, rank
    allocate(dims(0))
    if (.not. h5_has(f, path)) then
      call read_fail(f, path, 'dataset missing', err)
      return
    end if
    call h5dopen_f(f%id, path, d, st)
    if (st /= 0) then
      call read_fail(f, path, 'not a dataset', err)
      return
    end if
    call h5dget_space_f(d, sp, st)
    call h5sget_simple_extent_ndims_f(sp, rank, st)
    if (rank >= 1 .and. rank <= 7) then
      call h5sget_simple_extent_dims_f(sp, hd(1:rank), mx(1:rank), st)
      dims = int(hd(1:rank))
    end if
    call h5sclose_f(sp, s2)
    call h5dclose_f(d, s2)
  end subroutine h5_shape

  subroutine read_fail(f, path, what, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, what
    type(error_t), allocatable, intent(inout) :: err
    call set_error(err, "file '"//f%path//"': "//path//": "//what)
  end subroutine read_fail

  !> Open dataset path after checking that its shape is want; d < 0 on failure (err set).
  subroutine open_checked(f, path, want, d, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer, intent(in) :: want(:)
    integer(hid_t), intent(out) :: d
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: dims(:)
    integer :: st
    d = -1
    call h5_shape(f, path, dims, err)
    if (allocated(err)) return
    if (size(dims) /= size(want)) then
      call read_fail(f, path, 'rank '//itoa(size(dims))//' where '// &
        itoa(size(want))//' is expected', err)
      return
    end if
    if (any(dims /= want)) then
      call read_fail(f, path, 'shape ('//shape_text(dims)//') where ('//shape_text(want)// &
        ') is expected', err)
      return
    end if
    call h5dopen_f(f%id, path, d, st)
    if (st /= 0) then
      d = -1
      call read_fail(f, path, 'cannot be opened', err)
    end if
  contains
    function shape_text(n) result(s)
      integer, intent(in) :: n(:)
      character(len=:), allocatable :: s
      integer :: k
      s = ''
      do k = 1, size(n)
        if (k > 1) s = s//', '
        s = s//itoa(n(k))
      end do
    end function shape_text
  end subroutine open_checked

  subroutine read_ds_r1(f, path, a, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    real(wp), intent(inout) :: a(:)
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: d
    integer :: st, s2
    call open_checked(f, path, shape(a), d, err)
    if (allocated(err)) return
    call h5dread_f(d, H5T_NATIVE_DOUBLE, a, shape(a, kind=hsize_t), st)
    call h5dclose_f(d, s2)
    if (st /= 0) call read_fail(f, path, 'read failed', err)
  end subroutine read_ds_r1

  subroutine read_ds_r2(f, path, a, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    real(wp), intent(inout) :: a(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: d
    integer :: st, s2
    call open_checked(f, path, shape(a), d, err)
    if (allocated(err)) return
    call h5dread_f(d, H5T_NATIVE_DOUBLE, a, shape(a, kind=hsize_t), st)
    call h5dclose_f(d, s2)
    if (st /= 0) call read_fail(f, path, 'read failed', err)
  end subroutine read_ds_r2

  subroutine read_ds_i64(f, path, a, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer(i64), intent(inout) :: a(:)
    type(error_t), allocatable, intent(inout) :: err
    integer(i64), allocatable, target :: buf(:)
    type(c_ptr) :: ptr
    integer(hid_t) :: d
    integer :: st, s2
    call open_checked(f, path, shape(a), d, err)
    if (allocated(err)) return
    allocate(buf(size(a)))
    ptr = c_loc(buf)
    call h5dread_f(d, h5kind_to_type(i64, H5_INTEGER_KIND), ptr, st)
    call h5dclose_f(d, s2)
    if (st /= 0) then
      call read_fail(f, path, 'read failed', err)
      return
    end if
    a = buf
  end subroutine read_ds_i64

  subroutine read_ds_i64_2(f, path, a, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer(i64), intent(inout) :: a(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer(i64), allocatable, target :: buf(:, :)
    type(c_ptr) :: ptr
    integer(hid_t) :: d
    integer :: st, s2
    call open_checked(f, path, shape(a), d, err)
    if (allocated(err)) return
    allocate(buf(size(a, 1), size(a, 2)))
    ptr = c_loc(buf)
    call h5dread_f(d, h5kind_to_type(i64, H5_INTEGER_KIND), ptr, st)
    call h5dclose_f(d, s2)
    if (st /= 0) then
      call read_fail(f, path, 'read failed', err)
      return
    end if
    a = buf
  end subroutine read_ds_i64_2

  !> A text dataset written by h5_text, whole.
  subroutine h5_read_text(f, path, text, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: d, ft, mt
    integer(size_t) :: n
    integer(hsize_t) :: dims(1)
    integer :: st, s2
    text = ''
    if (.not. h5_has(f, path)) then
      call read_fail(f, path, 'dataset missing', err)
      return
    end if
    call h5dopen_f(f%id, path, d, st)
    if (st /= 0) then
      call read_fail(f, path, 'not a dataset', err)
      return
    end if
    call h5dget_type_f(d, ft, st)
    if (st == 0) call h5tget_size_f(ft, n, st)
    call h5tclose_f(ft, s2)
    if (st /= 0 .or. n < 1) then
      call h5dclose_f(d, s2)
      call read_fail(f, path, 'not a text dataset', err)
      return
    end if
    deallocate(text)
    allocate(character(len=int(n)) :: text)
    dims = 1
    call h5tcopy_f(H5T_FORTRAN_S1, mt, st)
    call h5tset_size_f(mt, n, st)
    call h5dread_f(d, mt, text, dims, st)
    call h5tclose_f(mt, s2)
    call h5dclose_f(d, s2)
    if (st /= 0) call read_fail(f, path, 'not a text dataset', err)
  end subroutine h5_read_text

  !> Open attribute name of object path; a < 0 on failure (err set).
  subroutine open_attr(f, path, name, obj, a, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name
    integer(hid_t), intent(out) :: obj, a
    type(error_t), allocatable, intent(inout) :: err
    integer :: st, s2
    a = -1
    obj = -1
    if (.not. h5_has_attr(f, path, name)) then
      call read_fail(f, path, "attribute '"//name//"' missing", err)
      return
    end if
    call h5oopen_f(f%id, path, obj, st)
    if (st == 0) call h5aopen_f(obj, name, a, st)
    if (st /= 0) then
      if (obj >= 0) call h5oclose_f(obj, s2)
      a = -1
      call read_fail(f, path, "attribute '"//name//"' cannot be opened", err)
    end if
  end subroutine open_attr

  subroutine close_attr(obj, a)
    integer(hid_t), intent(in) :: obj, a
    integer :: s2
    call h5aclose_f(a, s2)
    call h5oclose_f(obj, s2)
  end subroutine close_attr

  subroutine read_attr_str(f, path, name, val, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name
    character(len=:), allocatable, intent(out) :: val
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: obj, a, ft, mt
    integer(size_t) :: n
    integer(hsize_t) :: dims(1)
    integer :: st, s2
    val = ''
    call open_attr(f, path, name, obj, a, err)
    if (allocated(err)) return
    call h5aget_type_f(a, ft, st)
    if (st == 0) call h5tget_size_f(ft, n, st)
    call h5tclose_f(ft, s2)
    if (st /= 0 .or. n < 1) then
      call close_attr(obj, a)
      call read_fail(f, path, "attribute '"//name//"' is not text", err)
      return
    end if
    deallocate(val)
    allocate(character(len=int(n)) :: val)
    dims = 1
    call h5tcopy_f(H5T_FORTRAN_S1, mt, st)
    call h5tset_size_f(mt, n, st)
    call h5aread_f(a, mt, val, dims, st)
    call h5tclose_f(mt, s2)
    call close_attr(obj, a)
    if (st /= 0) call read_fail(f, path, "attribute '"//name//"' is not text", err)
  end subroutine read_attr_str

  subroutine read_attr_int(f, path, name, val, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name
    integer, intent(out) :: val
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: obj, a
    integer(hsize_t) :: dims(1)
    integer :: st
    val = 0
    call open_attr(f, path, name, obj, a, err)
    if (allocated(err)) return
    dims = 1
    call h5aread_f(a, H5T_NATIVE_INTEGER, val, dims, st)
    call close_attr(obj, a)
    if (st /= 0) call read_fail(f, path, "attribute '"//name//"' is not an integer", err)
  end subroutine read_attr_int

  !> A real attribute of one value (h5_attr writes a real scalar as a 1-element array).
  subroutine read_attr_real(f, path, name, val, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name
    real(wp), intent(out) :: val
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: v(1)
    v = 0.0_wp
    call read_attr_r1(f, path, name, v, err)
    val = v(1)
  end subroutine read_attr_real

  !> A real attribute of exactly size(val) values (attributes written by h5_attr).
  subroutine read_attr_r1(f, path, name, val, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: path, name
    real(wp), intent(inout) :: val(:)
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: obj, a, sp
    integer(hsize_t) :: dims(1), mx(1)
    integer :: st, s2, rank
    call open_attr(f, path, name, obj, a, err)
    if (allocated(err)) return
    call h5aget_space_f(a, sp, st)
    call h5sget_simple_extent_ndims_f(sp, rank, st)
    dims = 0
    if (rank == 1) call h5sget_simple_extent_dims_f(sp, dims, mx, st)
    call h5sclose_f(sp, s2)
    if (rank /= 1 .or. dims(1) /= size(val, kind=hsize_t)) then
      call close_attr(obj, a)
      call read_fail(f, path, "attribute '"//name//"' does not hold "// &
        itoa(size(val))//" values", err)
      return
    end if
    call h5aread_f(a, H5T_NATIVE_DOUBLE, val, dims, st)
    call close_attr(obj, a)
    if (st /= 0) call read_fail(f, path, "attribute '"//name//"' is not real", err)
  end subroutine read_attr_r1
end module hdf5_io_m
