!> Output of a dynamic run: particle snapshots at the deck's times (with an XDMF file so
!! ParaView opens the series), the energy history as extendible time series, and the run
!! summary as attributes of /summary. Layout: doc/output.md.
module dynamic_output_m
  use kinds_m, only: wp
  use dims_m, only: dims_t
  use errors_m, only: error_t
  use strings_m, only: itoa
  use solid_m, only: solid_t, solid_positions, at_prediction
  use tl_kinematics_m, only: physical_positions, jacobian
  use hdf5_io_m, only: h5file_t, h5_write_rows, h5_group, h5_write, h5_attr, h5_series_create, &
    h5_series_append, h5_flush
  implicit none
  private
  public :: history_t, history_names, snapshot_write, history_create, history_flush
  public :: history_push, xdmf_write, xdmf_body_t, history_width, body_columns, pair_columns
  public :: history_geometry, hist_plane, hist_axisym, hist_3d

  !> The geometries whose history columns differ: plane strain (per unit thickness),
  !! axisymmetry (per radian... the whole body: J, N), three dimensions (history_geometry).
  integer, parameter :: hist_plane = 1, hist_axisym = 2, hist_3d = 3
  public :: rigid_snapshot_write, output_rows

  !> A rigid body as the output shows it: a fixed one on its reference positions
  !! /bodies/<name>/x at every time step (no snapshot data); a moving one (a ram: its &body
  !! velocity, prescribed) at x + vel t, written in each snapshot (rigid_snapshot_write).
  type :: xdmf_body_t
    character(len=64) :: name = ''
    integer :: np = 0          !< particles (nodes)
    integer :: ne = 0          !< CST4 triangles (/bodies/<name>/triangles); 0: particles
    integer :: ndim = 2
    logical :: moving = .false.
    real(wp) :: vel(3) = 0.0_wp          !< its prescribed velocity (m/s)
    real(wp), allocatable :: x(:, :)     !< reference positions (ndim, np) (m), if moving
  end type xdmf_body_t

  !> Columns of /history, one row per history step.
  character(len=*), parameter :: history_names(17) = [character(len=14) :: &
    'step', 'time', 'dt', 'dt_critical', 'ke', 'w_int', 'w_plastic', 'w_ext', 'w_contact', &
    'residual', &
    'n_contact', 'f_contact', 'contact_radius', 'penetration', 'length', 'foot_radius', &
    'impulse']
  character(len=*), parameter :: history_units(17) = [character(len=4) :: &
    '1', 's', 's', 's', 'J', 'J', 'J', 'J', 'J', 'J', '1', 'N', 'm', 'm', 'm', 'm', 'N s']
  character(len=*), parameter :: history_descr(17) = [character(len=96) :: &
    'step number', 'time', 'time step', &
    'critical step estimate at the current deformation (dt_crit(0) sqrt(kappa0/kappa))', &
    'kinetic energy', &
    'internal work, int P:dF dV0 (stored plus dissipated)', 'plastic dissipation', &
    'work of external forces and kinematic conditions', 'work of contact forces', &
    'energy residual ke + w_int - ke(0) - w_ext - w_contact', &
    'slave particles with a contact force this step', &
    'mean normal contact force of the step (impulse / dt: half the eq. 93 sum)', &
    'largest x1 (r) of a slave particle in contact', &
    'deepest penetration left after the contact correction', &
    'extent in x2 (z) of the first deformable body', &
    'largest x1 (r) of the first deformable body within one spacing of its lowest x2', &
    'normal contact impulse since t = 0, the sum of f_contact dt over every step']

  !> Columns of /history/bodies/<name>/ for each deformable body: in plane strain the
  !! kinetic energy, the momentum sum_I M_I v_I and the angular momentum about the body's
  !! centre of mass, sum_I M_I (x_I - x_c) x (v_I - v_c) (x_I = X_I + d_I; with the
  !! coefficients of eqs. (65)-(67) the internal forces of the total-Lagrangian solid
  !! exert no net force or moment, so a free body keeps both); in axisymmetry the kinetic
  !! energy and the axial momentum; in 3D the momentum's and the angular momentum's three
  !! components and the extents along the three axes.
  character(len=*), parameter :: body_plane_names(7) = [character(len=16) :: 'ke', &
    'momentum_x', 'momentum_y', 'angular_momentum', 'extent_x', 'extent_y', 'max_epsbar']
  character(len=*), parameter :: body_axi_names(6) = [character(len=16) :: 'ke', &
    'momentum_z', 'length', 'radius', 'foot_radius', 'max_epsbar']
  character(len=*), parameter :: body_3d_names(11) = [character(len=18) :: 'ke', &
    'momentum_x', 'momentum_y', 'momentum_z', 'angular_momentum_x', 'angular_momentum_y', &
    'angular_momentum_z', 'extent_x', 'extent_y', 'extent_z', 'max_epsbar']
  character(len=*), parameter :: body_3d_units(11) = [character(len=4) :: 'J', 'N s', &
    'N s', 'N s', 'J s', 'J s', 'J s', 'm', 'm', 'm', '1']
  character(len=*), parameter :: body_3d_descr(11) = [character(len=96) :: &
    'kinetic energy of the body', 'momentum of the body, x', 'momentum of the body, y', &
    'momentum of the body, z', 'angular momentum of the body about its centre of mass, x', &
    'angular momentum of the body about its centre of mass, y', &
    'angular momentum of the body about its centre of mass, z', &
    'extent of the body in x (its physical nodes)', &
    'extent of the body in y (its physical nodes)', &
    'extent of the body in z (its physical nodes)', &
    'largest effective plastic strain in the body']
  character(len=*), parameter :: body_plane_units(7) = [character(len=4) :: 'J', 'N s', &
    'N s', 'J s', 'm', 'm', '1']
  character(len=*), parameter :: body_axi_units(6) = [character(len=4) :: 'J', 'N s', 'm', &
    'm', 'm', '1']
  character(len=*), parameter :: body_plane_descr(7) = [character(len=96) :: &
    'kinetic energy of the body', 'momentum of the body, x', 'momentum of the body, y', &
    'angular momentum of the body about its centre of mass (out of the plane)', &
    'extent of the body in x (its physical nodes)', &
    'extent of the body in y (its physical nodes)', &
    'largest effective plastic strain in the body']
  character(len=*), parameter :: body_axi_descr(6) = [character(len=96) :: &
    'kinetic energy of the body', 'momentum of the body along the axis', &
    'extent of the body along the axis z (a Taylor bar''s length)', &
    'extent of the body in r (its radius when it reaches the axis)', &
    'largest r within one spacing of the body''s lowest z (a Taylor bar''s foot radius)', &
    'largest effective plastic strain in the body']

  !> Columns of /history/contacts/contact<k>/ for each &contact pair k (in deck order): the
  !! mean normal and friction forces of the step (half the sums of the eq. (93) and
  !! (94)-(96) magnitudes: the impulse dt/2 f each gives, over dt), the resultant force on
  !! the slave body, in x, y (r, z in axisymmetry), and the friction work since t = 0.
  character(len=*), parameter :: pair_plane_names(5) = [character(len=16) :: &
    'force_normal', 'force_tangential', 'force_x', 'force_y', 'w_friction']
  character(len=*), parameter :: pair_axi_names(5) = [character(len=16) :: &
    'force_normal', 'force_tangential', 'force_r', 'force_z', 'w_friction']
  character(len=*), parameter :: pair_3d_names(6) = [character(len=16) :: &
    'force_normal', 'force_tangential', 'force_x', 'force_y', 'force_z', 'w_friction']
  character(len=*), parameter :: pair_3d_units(6) = [character(len=4) :: 'N', 'N', 'N', &
    'N', 'N', 'J']
  character(len=*), parameter :: pair_units(5) = [character(len=4) :: 'N', 'N', 'N', 'N', &
    'J']
  character(len=*), parameter :: pair_descr(6) = [character(len=96) :: &
    'mean normal contact force of the step (half the sum of the eq. 93 forces)', &
    'mean friction force of the step (half the sum of the eq. 94-96 magnitudes)', &
    'resultant contact force on the slave body, first component', &
    'resultant contact force on the slave body, second component', &
    'resultant contact force on the slave body, third component', &
    'friction work since t = 0 on the slip left after each correction (<= 0: dissipated)']

  !> History rows kept in memory until flushed to the file: the run's columns
  !! (history_names), then those of each deformable body (body_columns).
  type :: history_t
    real(wp), allocatable :: rows(:, :)   !< (columns, capacity)
    integer :: n = 0                      !< rows held
    integer :: nflushed = 0               !< rows already in the file
    character(len=:), allocatable :: paths(:)   !< each column's dataset
  end type history_t

contains

  !> The history's geometry: hist_plane, hist_axisym or hist_3d.
  pure integer function history_geometry(ndim, axisym) result(g)
    integer, intent(in) :: ndim
    logical, intent(in) :: axisym
    g = hist_plane
    if (axisym) g = hist_axisym
    if (ndim == 3) g = hist_3d
  end function history_geometry

  !> Columns of one deformable body in /history/bodies/<name>/.
  pure integer function body_columns(geometry) result(n)
    integer, intent(in) :: geometry
    select case (geometry)
    case (hist_axisym)
      n = size(body_axi_names)
    case (hist_3d)
      n = size(body_3d_names)
    case default
      n = size(body_plane_names)
    end select
  end function body_columns

  !> Columns of one contact pair in /history/contacts/contact<k>/.
  pure integer function pair_columns(geometry) result(n)
    integer, intent(in) :: geometry
    n = size(pair_plane_names)
    if (geometry == hist_3d) n = size(pair_3d_names)
  end function pair_columns

  !> Columns of a history row with nbodies deformable bodies, npairs contact pairs and nbcs
  !! &bc groups.
  pure integer function history_width(nbodies, npairs, nbcs, geometry) result(n)
    integer, intent(in) :: nbodies, npairs, nbcs, geometry
    n = size(history_names) + nbodies*body_columns(geometry) + npairs*pair_columns(geometry) &
      + nbcs
  end function history_width

  !> Create /history with one extendible dataset per column, and /history/bodies/<name>/
  !! with those of each deformable body (names, in the order of the solids).
  subroutine history_create(f, h, names, npairs, nbcs, geometry, err)
    type(h5file_t), intent(in) :: f
    type(history_t), intent(out) :: h
    character(len=*), intent(in) :: names(:)
    integer, intent(in) :: npairs, nbcs, geometry
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, b, c, nc
    character(len=:), allocatable :: g
    logical :: plane
    plane = geometry == hist_plane
    nc = history_width(size(names), npairs, nbcs, geometry)
    allocate(h%rows(nc, 1024))
    allocate(character(len=max(len('/history/bodies//') + len(names), 40) + 20) :: &
      h%paths(nc))
    call h5_group(f, '/history', err)
    do k = 1, size(history_names)
      if (allocated(err)) return
      h%paths(k) = '/history/'//trim(history_names(k))
      call h5_series_create(f, trim(h%paths(k)), plane_units(history_units(k)), err, &
        trim(history_descr(k)))
    end do
    if (size(names) > 0 .and. .not. allocated(err)) call h5_group(f, '/history/bodies', err)
    k = size(history_names)
    do b = 1, size(names)
      if (.not. allocated(err)) call h5_group(f, '/history/bodies/'//trim(names(b)), err)
      do c = 1, body_columns(geometry)
        if (allocated(err)) return
        k = k + 1
        select case (geometry)
        case (hist_plane)
          h%paths(k) = '/history/bodies/'//trim(names(b))//'/'//trim(body_plane_names(c))
          call h5_series_create(f, trim(h%paths(k)), plane_units(body_plane_units(c)), err, &
            trim(body_plane_descr(c)))
        case (hist_3d)
          h%paths(k) = '/history/bodies/'//trim(names(b))//'/'//trim(body_3d_names(c))
          call h5_series_create(f, trim(h%paths(k)), trim(body_3d_units(c)), err, &
            trim(body_3d_descr(c)))
        case default
          h%paths(k) = '/history/bodies/'//trim(names(b))//'/'//trim(body_axi_names(c))
          call h5_series_create(f, trim(h%paths(k)), trim(body_axi_units(c)), err, &
            trim(body_axi_descr(c)))
        end select
      end do
    end do
    if (npairs > 0 .and. .not. allocated(err)) call h5_group(f, '/history/contacts', err)
    do b = 1, npairs
      g = '/history/contacts/contact'//itoa(b)
      if (.not. allocated(err)) call h5_group(f, g, err)
      do c = 1, pair_columns(geometry)
        if (allocated(err)) return
        k = k + 1
        select case (geometry)
        case (hist_3d)
          h%paths(k) = g//'/'//trim(pair_3d_names(c))
          call h5_series_create(f, trim(h%paths(k)), trim(pair_3d_units(c)), err, &
            trim(pair_descr(c)))
        case default
          h%paths(k) = g//'/'//trim(merge(pair_plane_names(c), pair_axi_names(c), plane))
          ! (the plane's five columns: the descriptions without the third component's)
          call h5_series_create(f, trim(h%paths(k)), plane_units(pair_units(c)), err, &
            trim(pair_descr(merge(c, c + 1, c < 5))))
        end select
      end do
    end do
    ! /history/bcs/bc<k>/reaction: the force the k-th &bc group exerts on its body, in its
    ! component (R = f_int - f_ext summed over the nodes it holds)
    if (nbcs > 0 .and. .not. allocated(err)) call h5_group(f, '/history/bcs', err)
    do b = 1, nbcs
      if (allocated(err)) return
      g = '/history/bcs/bc'//itoa(b)
      call h5_group(f, g, err)
      k = k + 1
      h%paths(k) = g//'/reaction'
      if (.not. allocated(err)) call h5_series_create(f, trim(h%paths(k)), &
        plane_units('N'), err, 'force the &bc group exerts on its body, in its component '// &
        '(sum of f_int - f_ext over the components it holds)')
    end do

  contains

    !> Units per unit thickness in plane strain.
    function plane_units(unit) result(u)
      character(len=*), intent(in) :: unit
      character(len=:), allocatable :: u
      u = trim(unit)
      if (plane .and. u /= '1' .and. u /= 's' .and. u /= 'm') u = u//'/m'
    end function plane_units
  end subroutine history_create

  !> Keep one row.
  subroutine history_push(h, row)
    type(history_t), intent(inout) :: h
    real(wp), intent(in) :: row(:)
    real(wp), allocatable :: tmp(:, :)
    if (h%n == size(h%rows, 2)) then
      allocate(tmp(size(h%rows, 1), 2*size(h%rows, 2)))
      tmp(:, 1:h%n) = h%rows(:, 1:h%n)
      call move_alloc(tmp, h%rows)
    end if
    h%n = h%n + 1
    h%rows(:, h%n) = row
  end subroutine history_push

  !> Append the rows not yet in the file, and flush the file.
  subroutine history_flush(f, h, err)
    type(h5file_t), intent(in) :: f
    type(history_t), intent(inout) :: h
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    do k = 1, size(h%paths)
      if (allocated(err)) return
      call h5_series_append(f, trim(h%paths(k)), h%rows(k, h%nflushed + 1:h%n), err)
    end do
    h%nflushed = h%n
    call h5_flush(f)
  end subroutine history_flush

  !> /snapshots/<label>/<body>: physical positions, displacements and velocities of the
  !! particles, Cauchy stress, effective plastic strain and J (averaged over each particle's
  !! integration points with their weights; for SCNI the particle's own point), and the
  !! mean contact force on each particle's physical point since the previous snapshot
  !! (its impulse over the time between; the impulse is then restarted). A solid that is a
  !! rank's part (a file opened on every rank with MPI-IO, collectively) writes the rows of
  !! its own nodes and points into the whole solid's datasets, by their global numbers: its
  !! ghost points' stresses come from their owners first, and each own node's mean visits
  !! its points in global order, as the whole solid's does (the same bits).
  subroutine snapshot_write(f, label, time, step, solids, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: label
    real(wp), intent(in) :: time
    integer, intent(in) :: step
    type(solid_t), intent(inout) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: g, gb
    real(wp), allocatable :: vphys(:, :), sig(:, :), eps(:), jj(:), w(:), fc(:, :), pv(:, :)
    real(wp), allocatable :: xo(:, :), so(:, :), ro(:)
    integer, allocatable :: on(:), gn(:), oq(:), gq(:)
    integer :: k, q, np, e, i, nd, nc, nn, nqw
    character(len=:), allocatable :: vec, ten
    g = '/snapshots/'//label
    call h5_group(f, g, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'time', time, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'step', step, err)
    do k = 1, size(solids)
      if (allocated(err)) return
      associate (tb => solids(k))
        np = tb%np
        nd = tb%t%dims%ndim
        nc = tb%t%dims%ncomp
        vec = ' ('//itoa(nd)//', np)'
        ten = ' ('//itoa(nc)//', np)'
        gb = g//'/'//trim(tb%name)
        call output_rows(tb, on, gn, nn, oq, gq, nqw)
        call solid_positions(tb, at_prediction, tb%x)
        allocate(vphys(nd, np), sig(nc, np), eps(np), jj(np), w(np), fc(nd, np))
        call physical_positions(tb%t, 0.0_wp*tb%x0, tb%state%v, vphys)
        ! each point's tau, epsbar and J (a part's ghost points' from their owners)
        allocate(pv(nc + 2, tb%nq))
        do q = 1, tb%nq
          pv(1:nc, q) = tb%state%st%tau(:, q)
          pv(nc + 1, q) = tb%state%st%epsbar(q)
          pv(nc + 2, q) = jacobian(tb%state%f(:, q))
        end do
        if (tb%part%on) call tb%part%halo%points(pv)
        sig = 0.0_wp
        eps = 0.0_wp
        jj = 0.0_wp
        w = 0.0_wp
        ! nodal values: the weighted mean over the points a node owns (an SCNI cell), or
        ! over the points it belongs to when points have no owner (elements); a part's
        ! ghost point whose owner node is elsewhere adds to none of its nodes
        do q = 1, tb%nq
          if (tb%t%owner(q) > 0) then
            call accumulate(tb%t%owner(q))
          else if (tb%t%owner(q) == 0) then
            do e = tb%t%ptr(q), tb%t%ptr(q + 1) - 1
              call accumulate(tb%t%nbr(e))
            end do
          end if
        end do
        do i = 1, size(on)
          sig(:, on(i)) = sig(:, on(i))/w(on(i))
          eps(on(i)) = eps(on(i))/w(on(i))
          jj(on(i)) = jj(on(i))/w(on(i))
        end do
        fc = 0.0_wp
        if (tb%state%ipoint_time > 0.0_wp) fc = tb%state%ipoint/tb%state%ipoint_time
        tb%state%ipoint = 0.0_wp
        tb%state%ipoint_time = 0.0_wp
        ! (the rows into arrays of their own: a vector subscript as an argument would be a
        ! temporary each)
        xo = tb%x(:, on)
        call h5_group(f, gb, err)
        if (.not. allocated(err)) call h5_write_rows(f, gb//'/x', xo, gn, nn, 'm', err, &
          'physical particle positions'//vec)
        xo = xo - tb%x0(:, on)
        if (.not. allocated(err)) call h5_write_rows(f, gb//'/u', xo, gn, nn, 'm', err, &
          'particle displacements'//vec)
        xo = vphys(:, on)
        if (.not. allocated(err)) call h5_write_rows(f, gb//'/v', xo, gn, nn, 'm/s', err, &
          'particle velocities'//vec)
        so = sig(:, on)
        if (.not. allocated(err)) call h5_write_rows(f, gb//'/stress', so, gn, nn, 'Pa', err, &
          'Cauchy stress '//tensor_list(tb%t%dims)//hoop_note(tb)//ten)
        ro = eps(on)
        if (.not. allocated(err)) call h5_write_rows(f, gb//'/epsbar', ro, gn, nn, '1', err, &
          'effective plastic strain')
        ro = jj(on)
        if (.not. allocated(err)) call h5_write_rows(f, gb//'/J', ro, gn, nn, '1', err, &
          'volume ratio det F')
        xo = fc(:, on)
        if (.not. allocated(err)) call h5_write_rows(f, gb//'/f_contact', xo, gn, nn, &
          trim(merge('N  ', 'N/m', tb%t%axisym)), err, 'mean contact force on the particle''s '// &
          'physical point since the previous snapshot (impulse / time)'//vec)
        if (tb%t%interpolating .and. .not. allocated(err)) call cell_fields(tb, gb)
        deallocate(vphys, sig, eps, jj, w, fc, pv)
      end associate
    end do
    call h5_flush(f)
  contains
    subroutine accumulate(i)
      integer, intent(in) :: i
      sig(:, i) = sig(:, i) + solids(k)%t%wgt(q)*pv(1:nc, q)/pv(nc + 2, q)
      eps(i) = eps(i) + solids(k)%t%wgt(q)*pv(nc + 1, q)
      jj(i) = jj(i) + solids(k)%t%wgt(q)*pv(nc + 2, q)
      w(i) = w(i) + solids(k)%t%wgt(q)
    end subroutine accumulate

    !> Element (cell-centred) values of a finite-element body: the integration point's own.
    subroutine cell_fields(s, gb)
      type(solid_t), intent(in) :: s
      character(len=*), intent(in) :: gb
      real(wp), allocatable :: sc(:, :), jc(:), ec(:)
      integer :: qq, j
      allocate(sc(s%t%dims%ncomp, size(oq)), jc(size(oq)))
      ec = s%state%st%epsbar(oq)
      do j = 1, size(oq)
        qq = oq(j)
        jc(j) = jacobian(s%state%f(:, qq))
        sc(:, j) = s%state%st%tau(:, qq)/jc(j)
      end do
      call h5_write_rows(f, gb//'/stress_cells', sc, gq, nqw, 'Pa', err, &
        'Cauchy stress '//tensor_list(s%t%dims)//' of each element ('// &
        itoa(s%t%dims%ncomp)//', ne)')
      if (.not. allocated(err)) call h5_write_rows(f, gb//'/epsbar_cells', ec, gq, nqw, '1', &
        err, 'effective plastic strain of each element')
      if (.not. allocated(err)) call h5_write_rows(f, gb//'/J_cells', jc, gq, nqw, '1', err, &
        'volume ratio det F of each element')
    end subroutine cell_fields
  end subroutine snapshot_write

  !> The rows a file takes from solid s: its nodes on (local numbers) as numbers gn of the
  !! nn nodes of the whole solid, and its points oq as gq of nqw: all of them, or a rank's
  !! part's own.
  subroutine output_rows(s, on, gn, nn, oq, gq, nqw)
    type(solid_t), intent(in) :: s
    integer, allocatable, intent(out) :: on(:), gn(:), oq(:), gq(:)
    integer, intent(out) :: nn, nqw
    integer :: i
    if (s%part%on) then
      on = s%part%own_n
      gn = s%part%nglob(on)
      nn = s%part%np_whole
      oq = s%part%own_q
      gq = s%part%qglob(oq)
      nqw = s%part%nq_whole
    else
      on = [(i, i = 1, s%np)]
      gn = on
      nn = s%np
      oq = [(i, i = 1, s%nq)]
      gq = oq
      nqw = s%nq
    end if
  end subroutine output_rows

  !> The moving rigid bodies of rigid in snapshot label at time (s): positions x + vel t,
  !! displacements and velocities, as a deformable body's (without its fields).
  subroutine rigid_snapshot_write(f, label, time, rigid, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: label
    real(wp), intent(in) :: time
    type(xdmf_body_t), intent(in) :: rigid(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: gb, vec
    real(wp), allocatable :: u(:, :)
    integer :: k, i
    do k = 1, size(rigid)
      if (allocated(err)) return
      if (.not. rigid(k)%moving) cycle
      associate (b => rigid(k))
        gb = '/snapshots/'//label//'/'//trim(b%name)
        vec = ' ('//itoa(b%ndim)//', np)'
        allocate(u(b%ndim, b%np))
        do i = 1, b%np
          u(:, i) = b%vel(1:b%ndim)*time
        end do
        call h5_group(f, gb, err)
        if (.not. allocated(err)) call h5_write(f, gb//'/x', b%x + u, 'm', err, &
          'physical particle positions of the rigid body moving at its prescribed '// &
          'velocity'//vec)
        if (.not. allocated(err)) call h5_write(f, gb//'/u', u, 'm', err, &
          'particle displacements (velocity x t)'//vec)
        u = spread(b%vel(1:b%ndim), 2, b%np)
        if (.not. allocated(err)) call h5_write(f, gb//'/v', u, 'm/s', err, &
          'particle velocities (the prescribed velocity)'//vec)
        deallocate(u)
      end associate
    end do
  end subroutine rigid_snapshot_write

  !> '11, 22, 33, 12': the stored components of a symmetric tensor in the layout of dims.
  pure function tensor_list(dims) result(t)
    type(dims_t), intent(in) :: dims
    character(len=:), allocatable :: t
    integer :: c
    t = trim(dims%tensor_names(1))
    do c = 2, dims%ncomp
      t = t//', '//trim(dims%tensor_names(c))
    end do
  end function tensor_list

  !> What the 33 component is in axisymmetry (the plane layout's third).
  pure function hoop_note(s) result(t)
    type(solid_t), intent(in) :: s
    character(len=:), allocatable :: t
    t = ''
    if (s%t%dims%ndim == 2) t = ' (33: hoop in axisymmetry)'
  end function hoop_note

  !> The XDMF companion of the HDF5 file: a temporal collection of grids, one per snapshot
  !! and body (polyvertex for particles, triangles for CST4 meshes, with element fields),
  !! pointing at the datasets in the HDF5 file (ParaView opens it). The rigid bodies are in
  !! every snapshot too, on their reference positions and without fields.
  subroutine xdmf_write(path, h5name, labels, times, solids, rigid)
    character(len=*), intent(in) :: path, h5name
    character(len=*), intent(in) :: labels(:)
    real(wp), intent(in) :: times(:)
    type(solid_t), intent(in) :: solids(:)
    type(xdmf_body_t), intent(in) :: rigid(:)
    integer :: u, s, k, np
    character(len=:), allocatable :: g, nps, nes, nds
    open(newunit=u, file=path, status='replace', action='write')
    write(u, '(a)') '<?xml version="1.0" ?>'
    write(u, '(a)') '<Xdmf Version="3.0"><Domain>'
    write(u, '(a)') '<Grid Name="mfcd" GridType="Collection" CollectionType="Temporal">'
    do s = 1, size(labels)
      write(u, '(a)') '<Grid Name="t'//trim(labels(s))//'" GridType="Collection" '// &
        'CollectionType="Spatial">'
      write(u, '(a,es24.16,a)') '<Time Value="', times(s), '"/>'
      do k = 1, size(solids)
        np = solids(k)%np
        nps = itoa(np)
        g = h5name//':/snapshots/'//trim(labels(s))//'/'//trim(solids(k)%name)
        write(u, '(a)') '<Grid Name="'//trim(solids(k)%name)//'" GridType="Uniform">'
        if (solids(k)%t%interpolating .and. solids(k)%t%dims%ndim == 3) then
          nes = itoa(solids(k)%nq)
          write(u, '(a)') '<Topology TopologyType="Tetrahedron" NumberOfElements="'//nes// &
            '"><DataItem Dimensions="'//nes//' 4" Format="HDF" NumberType="Int" '// &
            'Precision="4">'//h5name//':/bodies/'//trim(solids(k)%name)//'/tetrahedra'// &
            '</DataItem></Topology>'
        else if (solids(k)%t%interpolating) then
          nes = itoa(solids(k)%nq)
          write(u, '(a)') '<Topology TopologyType="Triangle" NumberOfElements="'//nes// &
            '"><DataItem Dimensions="'//nes//' 3" Format="HDF" NumberType="Int" '// &
            'Precision="4">'//h5name//':/bodies/'//trim(solids(k)%name)//'/triangles'// &
            '</DataItem></Topology>'
        else
          write(u, '(a)') '<Topology TopologyType="Polyvertex" NumberOfElements="'//nps//'"/>'
        end if
        nds = itoa(solids(k)%t%dims%ndim)
        write(u, '(a)') '<Geometry GeometryType="'//trim(solids(k)%t%dims%axes)// &
          '"><DataItem Dimensions="'//nps//' '//nds//'" Format="HDF" NumberType="Float" '// &
          'Precision="8">'//g//'/x</DataItem></Geometry>'
        call attr(u, 'u', 'Vector', nps//' '//nds, g//'/u')
        call attr(u, 'v', 'Vector', nps//' '//nds, g//'/v')
        call components(u, 'stress', np, g//'/stress', 'Node', solids(k)%t%dims)
        call attr(u, 'epsbar', 'Scalar', nps, g//'/epsbar')
        call attr(u, 'J', 'Scalar', nps, g//'/J')
        call attr(u, 'f_contact', 'Vector', nps//' '//nds, g//'/f_contact')
        if (solids(k)%t%interpolating) then
          call attr(u, 'epsbar_cells', 'Scalar', nes, g//'/epsbar_cells', 'Cell')
          call components(u, 'stress_cells', solids(k)%nq, g//'/stress_cells', 'Cell', &
            solids(k)%t%dims)
          call attr(u, 'J_cells', 'Scalar', nes, g//'/J_cells', 'Cell')
        end if
        write(u, '(a)') '</Grid>'
      end do
      do k = 1, size(rigid)
        call rigid_grid(u, rigid(k), trim(labels(s)))
      end do
      write(u, '(a)') '</Grid>'
    end do
    write(u, '(a)') '</Grid></Domain></Xdmf>'
    close(u)
  contains
    !> Rigid body b at its reference positions (or, moving, where snapshot label has it): a
    !! Polyvertex grid over its particles, or a Triangle grid on its CST4 elements.
    subroutine rigid_grid(unit, b, label)
      integer, intent(in) :: unit
      type(xdmf_body_t), intent(in) :: b
      character(len=*), intent(in) :: label
      character(len=:), allocatable :: gb, nps, nes, geo, gx
      gb = h5name//':/bodies/'//trim(b%name)
      gx = gb
      if (b%moving) gx = h5name//':/snapshots/'//label//'/'//trim(b%name)
      nps = itoa(b%np)
      write(unit, '(a)') '<Grid Name="'//trim(b%name)//'" GridType="Uniform">'
      if (b%ne > 0) then
        nes = itoa(b%ne)
        write(unit, '(a)') '<Topology TopologyType="Triangle" NumberOfElements="'//nes// &
          '"><DataItem Dimensions="'//nes//' 3" Format="HDF" NumberType="Int" '// &
          'Precision="4">'//gb//'/triangles</DataItem></Topology>'
      else
        write(unit, '(a)') '<Topology TopologyType="Polyvertex" NumberOfElements="'//nps//'"/>'
      end if
      geo = 'XY'
      if (b%ndim == 3) geo = 'XYZ'
      write(unit, '(a)') '<Geometry GeometryType="'//geo//'"><DataItem Dimensions="'//nps// &
        ' '//itoa(b%ndim)//'" Format="HDF" NumberType="Float" Precision="8">'//gx// &
        '/x</DataItem></Geometry>'
      if (b%moving) then
        call attr(unit, 'u', 'Vector', nps//' '//itoa(b%ndim), gx//'/u')
        call attr(unit, 'v', 'Vector', nps//' '//itoa(b%ndim), gx//'/v')
      end if
      write(unit, '(a)') '</Grid>'
    end subroutine rigid_grid

    !> The stress components of the (n, ncomp) dataset item (in the plane 11, 22, 33, 12;
    !! axisymmetric: rr, zz, theta-theta, rz) as ncomp scalar attributes name_11, ...,
    !! each a HyperSlab of one column: VTK's XDMF readers take a 4-component 'Matrix' or
    !! 'Vector' attribute as one tuple or warn, while scalars read everywhere.
    subroutine components(unit, name, n, item, center, dims)
      integer, intent(in) :: unit, n
      character(len=*), intent(in) :: name, item, center
      type(dims_t), intent(in) :: dims
      integer :: c
      do c = 1, dims%ncomp
        write(unit, '(a)') '<Attribute Name="'//name//'_'//dims%tensor_names(c)// &
          '" AttributeType="Scalar" Center="'//center//'"><DataItem ItemType="HyperSlab" '// &
          'Dimensions="'//itoa(n)//' 1" Type="HyperSlab"><DataItem Dimensions="3 2" '// &
          'Format="XML">0 '//itoa(c - 1)//' 1 1 '//itoa(n)//' 1</DataItem><DataItem '// &
          'Dimensions="'//itoa(n)//' '//itoa(dims%ncomp)//'" Format="HDF" NumberType='// &
          '"Float" Precision="8">'//item//'</DataItem></DataItem></Attribute>'
      end do
    end subroutine components

    subroutine attr(unit, name, kind, dims, item, center)
      integer, intent(in) :: unit
      character(len=*), intent(in) :: name, kind, dims, item
      character(len=*), intent(in), optional :: center
      character(len=:), allocatable :: c
      c = 'Node'
      if (present(center)) c = center
      write(unit, '(a)') '<Attribute Name="'//name//'" AttributeType="'//kind// &
        '" Center="'//c//'"><DataItem Dimensions="'//dims//'" Format="HDF" '// &
        'NumberType="Float" Precision="8">'//item//'</DataItem></Attribute>'
    end subroutine attr
  end subroutine xdmf_write
end module dynamic_output_m
