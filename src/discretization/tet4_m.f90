!> Linear tetrahedra with averaged nodal pressure (Bonet and Burton, Commun. Numer. Meth.
!! Engng 14 (1998) 437-449; Bonet, Marriott and Hassan, Commun. Numer. Meth. Engng 17 (2001)
!! 551-561), the 3D finite element of the total-Lagrangian solid. This module builds the
!! mesh of an extruded body (generators_m extrude_body) and fills the discretization-neutral
!! tables of solid_tables_m, so the kernels of tl_kinematics3d_m (F, D, P, the internal
!! force of eq. 72) run on tetrahedra as they run on RKPM particles:
!!  - one integration point per tetrahedron, at its centroid, weight W = V (exact for the
!!    constant gradients);
!!  - nodal interpolation: the four linear shape functions, constant gradients (dims_3d,
!!    compact: dN/dX_j shared by the three components), the identity position table;
!!  - lumped mass by the row sum of the consistent mass (eq. 70), rho0 V/4 per node;
!!  - the tables flagged anp: solid_m replaces each tetrahedron's volume change by the mean
!!    of its nodes' (the averaged nodal pressure), which lifts the volumetric locking of
!!    linear tetrahedra in isochoric plastic flow.
!! The nodes are the body's particles, so contact and output see them as particles.
module tet4_m
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use body_m, only: body_t, extrusion_t, body_keep_used
  use generators_m, only: section_triangles, extruded_particle, extrude_pick
  use sorting_m, only: sorted_place, incidence_csr
  use dims_m, only: dims_3d
  use solid_tables_m, only: solid_tables_t, tables_finish_elements, element_rows
  use mesh_cells_m, only: check_cells, tet_volume
  implicit none
  private
  public :: face_nodes
  public :: tet4_mesh_t, tet4_extruded, tet4_prisms, tet4_tables, tet4_boundary_faces, &
    tet4_volume, tet4_face_neighbours, extruded_tets, tet4_region, tet4_section

  !> Tetrahedra over the nodes of a body_t.
  type :: tet4_mesh_t
    integer :: ne = 0                  !< tetrahedra
    integer, allocatable :: tet(:, :)  !< (4, ne) node numbers, positive volume
  end type tet4_mesh_t

  !> The faces of (1, 2, 3, 4) with a positive volume, face f opposite node f, each
  !! counter-clockwise seen from the side away from that node
  integer, parameter :: face_nodes(3, 4) = reshape([2, 3, 4, 1, 4, 3, 1, 2, 4, 1, 3, 2], &
    [3, 4])

contains

  !> The tetrahedra of b, the section b2 extruded in layers by extrude_body(b2, z0, z1, nz,
  !! b): the section's triangles (section_triangles: a lattice polygon's squares cut in two,
  !! a disk's fan and ring strips) times each layer give prisms, each cut into three
  !! tetrahedra (tet4_prisms). Refused when the section has no triangulation (a polygon
  !! whose outline leaves the lattice, a disk sector).
  subroutine tet4_extruded(b2, b, mesh, err)
    type(body_t), intent(in) :: b2, b
    type(tet4_mesh_t), intent(out) :: mesh
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: tri(:, :)
    integer :: nz
    if (b%ndim /= 3 .or. b2%np < 3 .or. mod(b%np, max(b2%np, 1)) /= 0) then
      call set_error(err, "body '"//trim(b%name)//"': tetrahedra need the 3D body extruded "// &
        'from its section (ndim = 3, a whole number of layers of the section''s '// &
        itoa(b2%np)//' particles), got ndim = '//itoa(b%ndim)//' and '//itoa(b%np)// &
        ' particles')
      return
    end if
    nz = b%np/b2%np
    call tet4_section(b2, b%name, tri, err)
    if (allocated(err)) return
    call tet4_prisms(b%x, tri, b2%np, nz, mesh, err)
  end subroutine tet4_extruded

  !> The triangles tri (3, nt) of the section b2 of body name that tet4_prisms cuts into
  !! tetrahedra (generators_m section_triangles), refused when it has none.
  subroutine tet4_section(b2, name, tri, err)
    type(body_t), intent(in) :: b2
    character(len=*), intent(in) :: name
    integer, allocatable, intent(out) :: tri(:, :)
    type(error_t), allocatable, intent(inout) :: err
    logical :: ok
    call section_triangles(b2, tri, ok)
    if (.not. ok) call set_error(err, "body '"//trim(name)//"': the section has no "// &
      'triangulation for tetrahedra (a polygon needs its vertices on lattice points; a '// &
      'cylinder must be whole, theta_end = 360): mesh it (gmsh) or use RKPM')
  end subroutine tet4_section

  !> The prisms of the section triangles tri (3, nt) over nz layers of n2 nodes (node (i, k)
  !! is i + (k - 1) n2, x (3, n2 nz) their positions), each cut into three tetrahedra. Each
  !! quadrilateral side face is cut along its diagonal from its lowest-numbered node
  !! (Dompierre, Labbe, Vallet and Camarero, 8th Int. Meshing Roundtable, 1999): the choice
  !! depends on the face alone, so neighbouring prisms cut their shared face alike and the
  !! mesh is conforming. With the section's nodes sorted p < q < r (the top ones p', q', r'
  !! numbered higher) the diagonals are p-q', p-r', q-r' and the prism is (p, q, r, r'),
  !! (p, q, r', q'), (p, q', r', p'). Every other layer takes the mirror cut (the section's
  !! order reversed: diagonals r-q', r-p', q-p'; still a rule of the face and its layer, so
  !! conforming), so the side faces' diagonals do not all lean one way along the body: with
  !! one cut throughout the Taylor bar's foot radius moved by 4.8% between the two cuts at
  !! 1 mm. Each tetrahedron's order is set for a positive volume.
  subroutine tet4_prisms(x, tri, n2, nz, mesh, err)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tri(:, :), n2, nz
    type(tet4_mesh_t), intent(out) :: mesh
    type(error_t), allocatable, intent(inout) :: err
    integer :: nt, m, k, e, t4(4), j
    real(wp) :: v
    nt = size(tri, 2)
    if (nz < 2 .or. nt < 1 .or. size(x, 1) /= 3 .or. size(x, 2) < n2*nz) then
      call set_error(err, 'tetrahedra of an extruded section: need 3D positions of '// &
        itoa(n2)//' x '//itoa(nz)//' nodes (at least 2 layers) and triangles, got '// &
        itoa(size(x, 2))//' nodes and '//itoa(nt)//' triangles')
      return
    end if
    if (any(tri < 1 .or. tri > n2)) then
      call set_error(err, 'tetrahedra of an extruded section: a triangle names a node '// &
        'outside 1..'//itoa(n2))
      return
    end if
    mesh%ne = 3*nt*(nz - 1)
    allocate(mesh%tet(4, mesh%ne))
    e = 0
    do k = 1, nz - 1
      do m = 1, nt
        do j = 1, 3
          t4 = prism_tet(tri(:, m), k, j, n2)
          v = tet4_volume(x(:, t4))
          if (v < 0.0_wp) t4(3:4) = t4([4, 3])
          if (.not. (abs(v) > 0.0_wp)) then
            call set_error(err, 'tetrahedra of an extruded section: triangle '//itoa(m)// &
              ' in layer '//itoa(k)//' gives a tetrahedron of zero volume (a degenerate '// &
              'section triangle)')
            return
          end if
          e = e + 1
          mesh%tet(:, e) = t4
        end do
      end do
    end do
  end subroutine tet4_prisms

  !> The nodes of tetrahedron j (1..3) of the prism over the section triangle tri3 in layer
  !! k of an extruded body of n2 nodes a layer, tet4_prisms' cut before its orientation:
  !! the section's nodes sorted p < q < r (reversed in the even layers: the mirror cut), the
  !! tetrahedra (p, q, r, r'), (p, q, r', q'), (p, q', r', p').
  pure function prism_tet(tri3, k, j, n2) result(t4)
    integer, intent(in) :: tri3(3), k, j, n2
    integer :: t4(4), s(3)
    s = sort3(tri3)
    if (mod(k, 2) == 0) s = s(3:1:-1)
    select case (j)
    case (1)
      t4 = [s(1), s(2), s(3), s(3) + n2]
    case (2)
      t4 = [s(1), s(2), s(3) + n2, s(2) + n2]
    case default
      t4 = [s(1), s(2) + n2, s(3) + n2, s(1) + n2]
    end select
    t4 = t4 + (k - 1)*n2
  end function prism_tet

  pure function sort3(a) result(b)
    integer, intent(in) :: a(3)
    integer :: b(3)
    b = a
    if (b(1) > b(2)) b([1, 2]) = b([2, 1])
    if (b(2) > b(3)) b([2, 3]) = b([3, 2])
    if (b(1) > b(2)) b([1, 2]) = b([2, 1])
  end function sort3

  !> The tetrahedra g0 ... g1 (tet (4, g1 - g0 + 1)) of the extruded body of recipe e, whose
  !! section's triangles are e%tri2 (tet4_extruded's mesh, tet4_prisms' numbering: layer,
  !! triangle, then the prism's three), without the mesh: the nodes as the body's numbers,
  !! each tetrahedron ordered for a positive volume from the positions as extrude_body made
  !! them (tet4_extruded's, to the bit). ok: .false. when one of them has zero volume (bad:
  !! its number).
  subroutine extruded_tets(e, g0, g1, tet, ok, bad)
    type(extrusion_t), intent(in) :: e
    integer, intent(in) :: g0, g1
    integer, allocatable, intent(out) :: tet(:, :)
    logical, intent(out) :: ok
    integer, intent(out) :: bad
    integer :: g
    logical :: okg
    allocate(tet(4, max(0, g1 - g0 + 1)))
    ok = .true.
    bad = 0
    do g = g0, g1
      call extruded_tet(e, g, tet(:, g - g0 + 1), okg)
      if (.not. okg .and. ok) bad = g
      ok = ok .and. okg
    end do
  end subroutine extruded_tets

  !> Tetrahedron g of the extruded body of recipe e (extruded_tets).
  pure subroutine extruded_tet(e, g, t4, ok)
    type(extrusion_t), intent(in) :: e
    integer, intent(in) :: g
    integer, intent(out) :: t4(4)
    logical, intent(out) :: ok
    real(wp) :: xt(3, 4), vol, v
    logical :: bnd
    integer :: nt, l
    nt = size(e%tri2, 2)
    t4 = prism_tet(e%tri2(:, mod((g - 1)/3, nt) + 1), (g - 1)/(3*nt) + 1, mod(g - 1, 3) + 1, &
      e%n2)
    do l = 1, 4
      call extruded_particle(e, mod(t4(l) - 1, e%n2) + 1, (t4(l) - 1)/e%n2 + 1, xt(:, l), &
        vol, bnd, as_made=.true.)
    end do
    v = tet4_volume(xt)
    if (v < 0.0_wp) t4(3:4) = t4([4, 3])
    ok = abs(v) > 0.0_wp
  end subroutine extruded_tet

  !> What a rank makes of the extruded body of tetrahedra b (its recipe b%ext with the
  !! section's triangles: the whole body is never made) for its box (3, 2) of the
  !! decomposition: the tetrahedra all of whose nodes lie within 2 l + s of the box (l the
  !! longest edge of the mesh, s the largest spacing, for the rounding), as mesh over the
  !! nodes of body r (generators_m extrude_pick's, cut to those the tetrahedra use), with
  !! their numbers in the whole mesh, eglob (ascending; ne_whole of them). They hold every
  !! tetrahedron tet4_tables keeps a row of for the box (its centroid or a vertex in it:
  !! every vertex within l of the box) and every tetrahedron of each of those rows' nodes
  !! (within l of such a vertex), in the whole mesh's order: those nodes' masses are the
  !! same sums in the same order as the whole body's.
  subroutine tet4_region(b, box, r, mesh, eglob, ne_whole, err)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: box(3, 2)
    type(body_t), intent(out) :: r
    type(tet4_mesh_t), intent(out) :: mesh
    integer, allocatable, intent(out) :: eglob(:)
    integer, intent(out) :: ne_whole
    type(error_t), allocatable, intent(inout) :: err
    type(body_t) :: near
    real(wp) :: lo(3), hi(3), l2, xa(2), xb(2), tlo(2), thi(2)
    integer :: none(2), nt, k, m, j, g, n, pass, l, t4(4), at(4), k0, k1
    real(wp) :: nowhere(2)
    logical, allocatable :: used(:), cross(:)
    logical :: ok
    associate (e => b%ext)
      nt = size(e%tri2, 2)
      ne_whole = 3*nt*(e%nz - 1)
      ! the longest edge: a prism's edges and its side faces' diagonals
      l2 = e%dz**2
      do m = 1, nt
        do j = 1, 3
          xa = e%x2(:, e%tri2(j, m))
          xb = e%x2(:, e%tri2(mod(j, 3) + 1, m))
          l2 = max(l2, sum((xa - xb)**2) + e%dz**2)
        end do
      end do
      lo = box(:, 1) - (2.0_wp*sqrt(l2) + maxval(b%spacing))
      hi = box(:, 2) + (2.0_wp*sqrt(l2) + maxval(b%spacing))
      none = 0
      nowhere = 0.0_wp
      call extrude_pick(b, 1, b%np, lo, hi, 0, none, nowhere, near)
      ! (the section's triangles with a node in the x-y range: the others' prisms have none)
      allocate(cross(nt))
      do m = 1, nt
        tlo = minval(e%x2(:, e%tri2(:, m)), dim=2)
        thi = maxval(e%x2(:, e%tri2(:, m)), dim=2)
        if (e%shifted) then
          tlo = tlo + e%shift(1:2)
          thi = thi + e%shift(1:2)
        end if
        cross(m) = all(thi >= lo(1:2)) .and. all(tlo <= hi(1:2))
      end do
      allocate(used(near%np))
      used = .false.
      k0 = 1
      k1 = 0
      if (near%np > 0) then
        k0 = (near%glob(1) - 1)/e%n2 + 1
        k1 = min((near%glob(near%np) - 1)/e%n2, e%nz - 1)
      end if
      do pass = 1, 2
        n = 0
        do k = k0, k1
          do m = 1, nt
            if (.not. cross(m)) cycle
            do j = 1, 3
              t4 = prism_tet(e%tri2(:, m), k, j, e%n2)
              do l = 1, 4
                at(l) = sorted_place(near%glob, t4(l))
              end do
              if (any(at == 0)) cycle
              n = n + 1
              if (pass == 1) cycle
              g = 3*(nt*(k - 1) + m - 1) + j
              call extruded_tet(e, g, t4, ok)
              if (.not. ok) then
                call set_error(err, 'tetrahedra of an extruded section: tetrahedron '// &
                  itoa(g)//' has zero volume (a degenerate section triangle)')
                return
              end if
              do l = 1, 4
                at(l) = sorted_place(near%glob, t4(l))
              end do
              used(at) = .true.
              mesh%tet(:, n) = at
              eglob(n) = g
            end do
          end do
        end do
        if (pass == 1) allocate(mesh%tet(4, n), eglob(n))
      end do
      mesh%ne = n
    end associate
    ! the nodes the tetrahedra use, renumbered
    call body_keep_used(near, used, mesh%tet(:, 1:mesh%ne), r)
  end subroutine tet4_region

  !> Signed volume of the tetrahedron xt (3, 4) (m^3): positive when node 4 lies on the side
  !! of the face (1, 2, 3) that its right-hand normal points to.
  pure real(wp) function tet4_volume(xt) result(v)
    real(wp), intent(in) :: xt(3, 4)
    v = tet_volume(xt, [1, 2, 3, 4])
  end function tet4_volume

  !> Gradients dn(:, k) = grad N_k (1/m) of the linear shape functions of the tetrahedron
  !! xt (3, 4), its volume v (m^3) and its smallest height 1/max_k |grad N_k| (m). With the
  !! edges e_k = X_{k+1} - X_1, grad N_{k+1} is the k-th column of [e_1 e_2 e_3]^-T, the
  !! cross product of the other two edges over 6 V; grad N_1 = -sum of the others.
  pure subroutine tet_gradients(xt, v, dn, hgt)
    real(wp), intent(in) :: xt(3, 4)
    real(wp), intent(out) :: v, dn(3, 4), hgt
    real(wp) :: e1(3), e2(3), e3(3), d6
    integer :: k
    e1 = xt(:, 2) - xt(:, 1)
    e2 = xt(:, 3) - xt(:, 1)
    e3 = xt(:, 4) - xt(:, 1)
    dn(:, 2) = cross(e2, e3)
    dn(:, 3) = cross(e3, e1)
    dn(:, 4) = cross(e1, e2)
    d6 = dot_product(e1, dn(:, 2))
    v = d6/6.0_wp
    hgt = 0.0_wp
    if (.not. (d6 > 0.0_wp)) return
    dn(:, 2:4) = dn(:, 2:4)/d6
    dn(:, 1) = -(dn(:, 2) + dn(:, 3) + dn(:, 4))
    hgt = huge(1.0_wp)
    do k = 1, 4
      hgt = min(hgt, 1.0_wp/norm2(dn(:, k)))
    end do
  contains
    pure function cross(a, b) result(c)
      real(wp), intent(in) :: a(3), b(3)
      real(wp) :: c(3)
      c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
    end function cross
  end subroutine tet_gradients

  !> Tables of the total-Lagrangian solid on the tetrahedra of mesh over the nodes of b
  !! (3D): one point per tetrahedron at its centroid with weight V, the constant gradients,
  !! lumped masses rho0 V/4 (rho0: density, kg/m^3), the identity position table, and the
  !! flag anp (solid_m averages the volume change over the nodes).
  !!
  !! box (3, 2), a rank's box of the decomposition (lower, upper corner; doc/parallel.md):
  !! the rows (nodes, gradients) are kept only for the tetrahedra whose centroid or a
  !! vertex lies in the box (closed), which holds every point the rank's part owns and
  !! every point touching a node it owns (decomposition_m local_part_build takes no other
  !! rows); the others' rows are empty, and the tables are not transposed (the split
  !! transposes the part's). Every tetrahedron's volume, centroid and height are computed
  !! all the same (a few flops each), so the masses, the smallest height and the checks
  !! are the whole body's on every rank, with no sum over the ranks.
  subroutine tet4_tables(b, mesh, rho0, t, err, box)
    type(body_t), intent(in) :: b
    type(tet4_mesh_t), intent(in) :: mesh
    real(wp), intent(in) :: rho0
    type(solid_tables_t), intent(out) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: box(3, 2)
    integer, allocatable :: touched(:)
    logical, allocatable :: keep(:)
    real(wp) :: xt(3, 4), dn(3, 4), v, hgt, hmin
    integer :: np, ne, e, k, i, bad
    np = b%np
    ne = mesh%ne
    call check_cells(b%name, b%ndim, b%np, mesh%tet, mesh%ne, 4, 3, 'tetrahedron', err)
    if (allocated(err)) return
    if (.not. (rho0 > 0.0_wp)) then
      call set_error(err, "body '"//trim(b%name)//"': tetrahedra density rho0 = "// &
        rtoa(rho0)//' must be positive')
      return
    end if
    t%np = np
    t%nq = ne
    t%dims = dims_3d
    t%scheme = 0
    t%axisym = .false.
    t%interpolating = .true.
    t%anp = .true.
    allocate(t%xq(3, ne), t%owner(ne), t%wgt(ne))
    t%owner = 0
    ! each tetrahedron writes only its own entries: no races
    hmin = huge(1.0_wp)
    bad = huge(0)
    !$omp parallel do default(none) shared(b, mesh, t, ne) private(xt, dn, v, hgt) &
    !$omp reduction(min: hmin, bad) schedule(static)
    do e = 1, ne
      xt = b%x(:, mesh%tet(:, e))
      call tet_gradients(xt, v, dn, hgt)
      t%xq(:, e) = 0.25_wp*sum(xt, dim=2)
      if (.not. (v > 0.0_wp)) then
        bad = min(bad, e)
        cycle
      end if
      hmin = min(hmin, hgt)
      t%wgt(e) = v
    end do
    !$omp end parallel do
    call element_rows(t, b%x, mesh%tet, keep, box)
    allocate(t%nbr(t%ptr(ne + 1) - 1), t%g(t%dims%ngrad, t%ptr(ne + 1) - 1), &
      t%h(t%ptr(ne + 1) - 1))
    t%h = 0.0_wp
    if (bad > ne) then
      !$omp parallel do default(none) shared(b, mesh, t, ne, keep) private(xt, dn, v, hgt, k, i) &
      !$omp schedule(static)
      do e = 1, ne
        if (.not. keep(e)) cycle
        xt = b%x(:, mesh%tet(:, e))
        call tet_gradients(xt, v, dn, hgt)
        do k = 1, 4
          i = t%ptr(e) + k - 1
          t%nbr(i) = mesh%tet(k, e)
          t%g(:, i) = dn(:, k)
        end do
      end do
      !$omp end parallel do
    end if
    if (bad <= ne) then
      xt = b%x(:, mesh%tet(:, bad))
      call set_error(err, "body '"//trim(b%name)//"': tetrahedron "//itoa(bad)//' (nodes '// &
        itoa(mesh%tet(1, bad))//', '//itoa(mesh%tet(2, bad))//', '//itoa(mesh%tet(3, bad))// &
        ', '//itoa(mesh%tet(4, bad))//') has volume '//rtoa(tet4_volume(xt))//' m^3: '// &
        'tetrahedra need a positive volume (node 4 on the side the right-hand normal of '// &
        '(1, 2, 3) points to)')
      return
    end if
    t%hmin = hmin
    ! lumped mass, row sums of the consistent mass (eq. 70): rho0 int N_I dV = rho0 V/4 (a
    ! scatter: serial)
    allocate(t%mass(np), touched(np))
    t%mass = 0.0_wp
    touched = 0
    do e = 1, ne
      do k = 1, 4
        i = mesh%tet(k, e)
        touched(i) = touched(i) + 1
        t%mass(i) = t%mass(i) + 0.25_wp*rho0*t%wgt(e)
      end do
    end do
    if (any(touched == 0)) then
      i = findloc(touched, 0, dim=1)
      call set_error(err, "body '"//trim(b%name)//"': node "//itoa(i)//' belongs to no '// &
        'tetrahedron (it would have no mass): remove it or mesh it')
      return
    end if
    allocate(t%fix1(np))
    t%fix1 = .false.
    ! nodal interpolation: the position table N_I(X_J) is the identity
    call tables_finish_elements(t, transpose=.not. present(box))
  end subroutine tet4_tables

  !> The boundary of the mesh over np nodes: the faces that belong to one tetrahedron only,
  !! faces (3, nf) ordered counter-clockwise seen from outside (the orientation of
  !! body_t%facets), and which tetrahedron each belongs to (owner, nf). A conforming mesh
  !! has every other face in exactly two tetrahedra; shared (optional) counts those and
  !! over (optional) the faces found in more than two (0 for a valid mesh).
  subroutine tet4_boundary_faces(mesh, np, faces, owner, shared, over)
    type(tet4_mesh_t), intent(in) :: mesh
    integer, intent(in) :: np
    integer, allocatable, intent(out) :: faces(:, :), owner(:)
    integer, intent(out), optional :: shared, over
    integer, allocatable :: nbr(:, :), cnt(:, :)
    integer :: e, f, nb
    call face_pairs(mesh, np, nbr, cnt)
    nb = count(cnt == 0)
    allocate(faces(3, nb), owner(nb))
    nb = 0
    do e = 1, mesh%ne
      do f = 1, 4
        if (cnt(f, e) /= 0) cycle
        nb = nb + 1
        faces(:, nb) = mesh%tet(face_nodes(:, f), e)
        owner(nb) = e
      end do
    end do
    if (present(shared)) shared = count(cnt == 1)/2
    if (present(over)) over = count(cnt > 1)
  end subroutine tet4_boundary_faces

  !> The tetrahedron across each face of each tetrahedron of the mesh over np nodes:
  !! nbr(f, e) across face f of e (the face opposite its node f; face_nodes), 0 on the
  !! boundary. A face in more than two tetrahedra (a mesh that is not conforming) is an
  !! error the callers report (tet4_boundary_faces' over); here it keeps the last match.
  subroutine tet4_face_neighbours(mesh, np, nbr)
    type(tet4_mesh_t), intent(in) :: mesh
    integer, intent(in) :: np
    integer, allocatable, intent(out) :: nbr(:, :)
    integer, allocatable :: cnt(:, :)
    call face_pairs(mesh, np, nbr, cnt)
  end subroutine tet4_face_neighbours

  !> The faces of the mesh's tetrahedra matched in pairs: cnt(f, e) the other faces equal
  !! to face f of e (0: a boundary face, 1: shared, more: not conforming), nbr(f, e) the
  !! tetrahedron of the last one found (0: none). Faces are bucketed by their smallest node
  !! (CSR), then compared within a bucket.
  subroutine face_pairs(mesh, np, nbr, cnt)
    type(tet4_mesh_t), intent(in) :: mesh
    integer, intent(in) :: np
    integer, allocatable, intent(out) :: nbr(:, :), cnt(:, :)
    integer, allocatable :: ptr(:), fid(:), amin(:, :)
    integer :: e, f, k, a, l, key(3), other(3), ek, fk, el, fl
    ! each face 4 (e - 1) + f by its smallest node, in that order within a node
    allocate(amin(1, 4*mesh%ne), cnt(4, mesh%ne), nbr(4, mesh%ne))
    do e = 1, mesh%ne
      do f = 1, 4
        amin(1, 4*(e - 1) + f) = minval(mesh%tet(face_nodes(:, f), e))
      end do
    end do
    call incidence_csr(amin, np, ptr, fid)
    deallocate(amin)
    cnt = 0
    nbr = 0
    do a = 1, np
      do k = ptr(a), ptr(a + 1) - 1
        key = face_key(fid(k))
        ek = (fid(k) - 1)/4 + 1
        fk = fid(k) - 4*(ek - 1)
        do l = k + 1, ptr(a + 1) - 1
          other = face_key(fid(l))
          if (all(key == other)) then
            el = (fid(l) - 1)/4 + 1
            fl = fid(l) - 4*(el - 1)
            cnt(fk, ek) = cnt(fk, ek) + 1
            cnt(fl, el) = cnt(fl, el) + 1
            nbr(fk, ek) = el
            nbr(fl, el) = ek
          end if
        end do
      end do
    end do
  contains
    pure function face_key(id) result(s)
      integer, intent(in) :: id
      integer :: s(3), ee, ff
      ee = (id - 1)/4 + 1
      ff = id - 4*(ee - 1)
      s = mesh%tet(face_nodes(:, ff), ee)
      if (s(1) > s(2)) s([1, 2]) = s([2, 1])
      if (s(2) > s(3)) s([2, 3]) = s([3, 2])
      if (s(1) > s(2)) s([1, 2]) = s([2, 1])
    end function face_key
  end subroutine face_pairs
end module tet4_m
