!> Parts of every mfcd output file: provenance attributes on '/', the deck verbatim, and
!! the bodies' reference particles. Layout: doc/output.md.
module run_output_m
  use kinds_m, only: wp
  use errors_m, only: error_t
  use version_m, only: code_name, code_version, git_commit
  use deck_m, only: deck_t
  use body_m, only: body_t
  use kernels_m, only: kernel_names, window_shape_names
  use hdf5_io_m, only: h5file_t, h5_group, h5_write, h5_attr, h5_text, h5_write_rows
  use material_m, only: material_constant_names, material_constant
  implicit none
  private
  public :: write_header, write_bodies, write_body_rows, timestamp

  !> /bodies/<name>/facets' description
  character(len=*), parameter :: facets_text = 'the closed boundary surface: particle '// &
    '(node) indices (0-based) of each triangle, counter-clockwise seen from outside (3, nf)'

contains

  !> ISO 8601 local time stamp.
  function timestamp() result(s)
    character(len=25) :: s
    integer :: v(8)
    character(len=1) :: sg
    call date_and_time(values=v)
    sg = merge('+', '-', v(4) >= 0)
    write(s, '(i4.4,"-",i2.2,"-",i2.2,"T",i2.2,":",i2.2,":",i2.2,a1,i2.2,":",i2.2)') &
      v(1), v(2), v(3), v(5), v(6), v(7), sg, abs(v(4))/60, mod(abs(v(4)), 60)
  end function timestamp

  !> Root attributes (code, version, commit, deck path, time, run parameters) and /deck.
  subroutine write_header(f, deck, err)
    type(h5file_t), intent(in) :: f
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    call h5_attr(f, '/', 'code', code_name, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'code_version', code_version, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'git_commit', git_commit, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'deck_path', deck%path, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'created', timestamp(), err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'title', trim(deck%run%title), err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'mode', trim(deck%run%mode), err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'ndim', deck%run%ndim, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'geometry', trim(deck%run%geometry), err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'units', 'SI (m, kg, s, Pa)', err)
    if (.not. allocated(err)) call h5_text(f, '/deck', deck%text, err)
    if (.not. allocated(err)) call write_materials(f, deck, err)
  end subroutine write_header

  !> /materials/<name>: the model, the preset the deck named, and every constant the model
  !! uses as an attribute, each with <constant>_source: 'given', 'preset' or 'default'.
  subroutine write_materials(f, deck, err)
    type(h5file_t), intent(in) :: f
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, j
    character(len=:), allocatable :: g
    if (deck%nmaterials == 0) return
    call h5_group(f, '/materials', err)
    do k = 1, deck%nmaterials
      associate (m => deck%materials(k))
        g = '/materials/'//trim(m%name)
        if (.not. allocated(err)) call h5_group(f, g, err)
        if (.not. allocated(err)) call h5_attr(f, g, 'model', trim(m%params%model), err)
        if (.not. allocated(err)) call h5_attr(f, g, 'preset', trim(m%preset), err)
        do j = 1, size(material_constant_names)
          if (allocated(err)) return
          if (len_trim(m%source(j)) == 0) cycle
          call h5_attr(f, g, trim(material_constant_names(j)), &
            material_constant(m%params, j), err)
          if (.not. allocated(err)) call h5_attr(f, g, trim(material_constant_names(j))// &
            '_source', trim(m%source(j)), err)
        end do
      end associate
    end do
  end subroutine write_materials

  !> /bodies/<name>: reference positions, volumes, supports, boundary and polylines. A
  !! body held as a rank's share (body_t row0 > 0, mfcd_mpi) gets its rows from every rank
  !! afterwards (write_body_rows, collectively), the rest here.
  subroutine write_bodies(f, bodies, deck, err)
    type(h5file_t), intent(in) :: f
    type(body_t), intent(in) :: bodies(:)
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, nd
    character(len=:), allocatable :: g
    call h5_group(f, '/bodies', err)
    do k = 1, size(bodies)
      if (allocated(err)) return
      associate (b => bodies(k))
        nd = b%ndim
        g = '/bodies/'//trim(b%name)
        call h5_group(f, g, err)
        if (b%row0 == 0 .and. .not. allocated(err)) call body_rows(f, b, err)
        if (.not. allocated(err)) call h5_write(f, g//'/loop_ptr', b%loop_ptr, '1', err, &
          'CSR pointer of boundary polylines (1-based, nloops + 1)')
        if (.not. allocated(err)) call h5_write(f, g//'/loop_idx', b%loop_idx, '1', err, &
          'particle indices (1-based) along each counter-clockwise boundary polyline')
        ! (a rank's rows of the facets: written with the body's rows, write_body_rows)
        if (allocated(b%facets) .and. b%ndim == 3 .and. b%facet0 == 0 .and. &
          .not. allocated(err)) call h5_write(f, g//'/facets', b%facets - 1, '1', err, &
          facets_text)
        if (.not. allocated(err)) call h5_attr(f, g, 'discretization', &
          trim(merge('fem ', 'rkpm', allocated(b%cells))), err)
        if (.not. allocated(err)) call h5_attr(f, g, 'shape', trim(b%shape), err)
        if (.not. allocated(err)) call h5_attr(f, g, 'kernel', trim(kernel_names(b%kid)), err)
        if (.not. allocated(err)) call h5_attr(f, g, 'window', &
          trim(window_shape_names(b%wshape)), err)
        if (.not. allocated(err)) call h5_attr(f, g, 'basis', trim(deck%bodies(k)%basis), err)
        if (.not. allocated(err)) call h5_attr(f, g, 'spacing', b%spacing(1:nd), err)
        if (.not. allocated(err)) call h5_attr(f, g, 'support_factor', &
          b%support_factor(1:nd), err)
        if (.not. allocated(err)) call h5_attr(f, g, 'basis_scale', b%h(1:nd), err)
        if (.not. allocated(err)) call h5_attr(f, g, 'np', b%np, err)
        if (.not. allocated(err)) call h5_attr(f, g, 'role', trim(deck%bodies(k)%role), err)
        if (deck%bodies(k)%role == 'rigid' .and. .not. allocated(err)) call h5_attr(f, g, &
          'velocity', deck%bodies(k)%velocity(1:nd), err)
      end associate
    end do
  end subroutine write_bodies

  !> The rows of the bodies held as ranks' shares (body_t row0 > 0): each rank writes its
  !! share into /bodies/<name> (its group made by write_bodies), collectively, in a file
  !! every rank has opened with MPI-IO; the same datasets as a whole body's.
  subroutine write_body_rows(f, bodies, err)
    type(h5file_t), intent(in) :: f
    type(body_t), intent(in) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    do k = 1, size(bodies)
      if (allocated(err)) return
      if (bodies(k)%row0 > 0) call body_rows(f, bodies(k), err)
    end do
  end subroutine write_body_rows

  !> Body b's datasets over its particles and elements: all of them (row0 = 0), or its
  !! share's rows of the whole body's datasets.
  subroutine body_rows(f, b, err)
    type(h5file_t), intent(in) :: f
    type(body_t), intent(in) :: b
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: gid(:), gc(:), flags(:), cells0(:, :)
    integer :: i, n0, c0, ne
    character(len=:), allocatable :: g
    character(len=3) :: vunit
    g = '/bodies/'//trim(b%name)
    vunit = 'm'
    if (b%ndim == 2) vunit = 'm^2'
    if (b%ndim == 3) vunit = 'm^3'
    n0 = max(b%row0, 1)
    gid = [(n0 + i - 1, i = 1, size(b%vol))]
    flags = merge(1, 0, b%boundary)
    call h5_write_rows(f, g//'/x', b%x, gid, b%np, 'm', err, &
      'reference particle positions (ndim, np)')
    if (.not. allocated(err)) call h5_write_rows(f, g//'/volume', b%vol, gid, b%np, &
      trim(vunit), err, 'particle volume Delta V (length in 1D, area in 2D)')
    if (.not. allocated(err)) call h5_write_rows(f, g//'/support', b%rho, gid, b%np, 'm', &
      err, 'support radius rho per direction (ndim, np)')
    if (.not. allocated(err)) call h5_write_rows(f, g//'/boundary', flags, gid, b%np, '1', &
      err, '1 for boundary particles')
    ! (a share's facets, facet0 ... of nfacets; a whole body's are write_bodies')
    if (allocated(b%facets) .and. b%ndim == 3 .and. b%facet0 > 0 .and. &
      .not. allocated(err)) then
      gid = [(b%facet0 + i - 1, i = 1, size(b%facets, 2))]
      cells0 = b%facets - 1
      call h5_write_rows(f, g//'/facets', cells0, gid, b%nfacets, '1', err, facets_text)
    end if
    if (.not. allocated(b%cells) .or. allocated(err)) return
    ! (a share's elements are cell0 ... of ncells; a whole body's all of its cells)
    c0 = max(b%cell0, 1)
    ne = b%ncells
    if (b%cell0 == 0) ne = size(b%cells, 2)
    gc = [(c0 + i - 1, i = 1, size(b%cells, 2))]
    cells0 = b%cells - 1
    if (b%ndim == 3) then
      call h5_write_rows(f, g//'/tetrahedra', cells0, gc, ne, '1', err, 'linear '// &
        'tetrahedra (averaged nodal pressure): node indices (0-based, as XDMF reads them), '// &
        'positive volume (4, ne)')
    else
      call h5_write_rows(f, g//'/triangles', cells0, gc, ne, '1', err, 'CST4 elements: '// &
        'node indices (0-based, as XDMF reads them) of each triangle, counter-clockwise '// &
        '(3, ne)')
    end if
  end subroutine body_rows
end module run_output_m
