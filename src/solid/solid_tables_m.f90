!> The discretization-neutral tables of the total-Lagrangian solid (Section 4): everything
!! that depends only on the reference configuration, computed once before the time loop,
!! whatever built them (RKPM with SCNI, Gauss or direct integration in rkpm_tl_m and
!! rkpm_tl3d_m; CST4 finite elements in cst4_m; linear tetrahedra in tet4_m).
!!
!! For each integration point L (an SCNI cell, a Gauss point, a triangle) the tables hold the
!! nodes I (RK particles or element nodes) whose shape functions touch it (CSR: ptr, nbr)
!! with the reference gradients g of their shape functions, the hoop term h (axisymmetry),
!! the weight W_L, plus the lumped masses (eq. 70), the table N_I(X_J) that turns
!! coefficients into physical positions (the identity for interpolating elements), and the
!! transpose that lets the internal force be gathered per node without write races.
module solid_tables_m
  use kinds_m, only: wp
  use dims_m, only: dims_t
  implicit none
  private
  public :: solid_tables_t, tables_transpose, tables_transpose_values, tables_move, &
    tables_copy_scalars, tables_finish_elements, element_rows

  type :: solid_tables_t
    integer :: np = 0                    !< particles (coefficient pairs)
    integer :: nq = 0                    !< integration points
    integer :: scheme = 0                !< how the tables were built (builder-specific id)
    !> the shapes of the geometry (dims_m), set by the builder: xq is (ndim, nq), g, gs
    !! and tg (ngrad, nnz), ws (ndim, nq), pn (npos, nnzp)
    type(dims_t) :: dims
    logical :: axisym = .false.
    !> nodal interpolation (finite elements): the physical position of node J is X_J + d_J,
    !! the position table is the identity and point forces need no redistribution (eq. 99)
    logical :: interpolating = .false.
    !> averaged nodal pressure (linear tetrahedra, tet4_m): the solid replaces each point's
    !! volume change by the mean of its nodes' before the material sees it (solid_m)
    logical :: anp = .false.
    real(wp), allocatable :: xq(:, :)    !< integration points, reference (m)
    !> node whose cell holds point L (0: none, e.g. an element; -1: on a rank's part, a
    !! ghost point whose node is not local)
    integer, allocatable :: owner(:)
    real(wp), allocatable :: wgt(:)      !< W_L (m^3 axisymmetric, m^2 per unit thickness)
    real(wp), allocatable :: mass(:)     !< lumped mass (kg, or kg/m in plane strain)
    integer, allocatable :: ptr(:)       !< CSR pointer over points (nq + 1)
    integer, allocatable :: nbr(:)       !< particle of each entry
    real(wp), allocatable :: g(:, :)     !< dN^i/dX_j, in the plane dN^1/dX1, dN^1/dX2, ... (1/m)
    real(wp), allocatable :: h(:)        !< (nnz): hoop term of N^1 (1/m), 0 in plane strain
    !> SCNI sub-cell stabilization (nnz): the right half-cell's smoothed d/dX1 of N^1, N^2
    !! and the upper half-cell's d/dX2 of N^1, N^2, each minus the whole cell's (1/m)
    real(wp), allocatable :: gs(:, :)
    real(wp), allocatable :: ws(:, :)    !< weights W_r (1 + W_r/W_l), W_u (1 + W_u/W_d)
    integer, allocatable :: tptr(:)      !< transpose pointer over particles (np + 1)
    integer, allocatable :: tent(:)      !< entries touching particle I (not in 3D)
    integer, allocatable :: tq(:)        !< their integration points
    !> g, h and gs in the transpose's order (tables_transpose_values): the force gather
    !! of eq. (72) reads them as one stream instead of through tent (th not in 3D)
    real(wp), allocatable :: tg(:, :), th(:), tgs(:, :)
    integer, allocatable :: pptr(:)      !< position table pointer (np + 1)
    integer, allocatable :: pnbr(:)
    real(wp), allocatable :: pn(:, :)    !< N^i_I(X_J), i = 1..ndim
    logical, allocatable :: fix1(:)      !< component 1 held at 0 (on the axis)
    real(wp) :: hmin = 0.0_wp            !< smallest particle spacing (m)
    real(wp) :: total_mass = 0.0_wp
    real(wp) :: total_volume = 0.0_wp
  end type solid_tables_t

contains

  !> The tables' scalars (counts, geometry, totals) from a to b: the one list of them, used
  !! by tables_move and by a rank's part (decomposition_m), which then sets its own counts.
  subroutine tables_copy_scalars(a, b)
    type(solid_tables_t), intent(in) :: a
    type(solid_tables_t), intent(inout) :: b
    b%np = a%np
    b%nq = a%nq
    b%scheme = a%scheme
    b%dims = a%dims
    b%axisym = a%axisym
    b%interpolating = a%interpolating
    b%anp = a%anp
    b%hmin = a%hmin
    b%total_mass = a%total_mass
    b%total_volume = a%total_volume
  end subroutine tables_copy_scalars

  !> a's tables moved into b without a copy of the arrays (a is left empty): the one list of
  !! the type's arrays. A component added to solid_tables_t is added here.
  subroutine tables_move(a, b)
    type(solid_tables_t), intent(inout) :: a
    type(solid_tables_t), intent(out) :: b
    call tables_copy_scalars(a, b)
    call move_alloc(a%xq, b%xq)
    call move_alloc(a%owner, b%owner)
    call move_alloc(a%wgt, b%wgt)
    call move_alloc(a%mass, b%mass)
    call move_alloc(a%ptr, b%ptr)
    call move_alloc(a%nbr, b%nbr)
    call move_alloc(a%g, b%g)
    call move_alloc(a%h, b%h)
    call move_alloc(a%gs, b%gs)
    call move_alloc(a%ws, b%ws)
    call move_alloc(a%tptr, b%tptr)
    call move_alloc(a%tent, b%tent)
    call move_alloc(a%tq, b%tq)
    call move_alloc(a%tg, b%tg)
    call move_alloc(a%th, b%th)
    call move_alloc(a%tgs, b%tgs)
    call move_alloc(a%pptr, b%pptr)
    call move_alloc(a%pnbr, b%pnbr)
    call move_alloc(a%pn, b%pn)
    call move_alloc(a%fix1, b%fix1)
  end subroutine tables_move

  !> The rows an element mesh keeps for a rank's box (the builders' box; doc/parallel.md):
  !! an element's when its point xq(:, e) or one of its vertices cells(:, e) (over the
  !! nodes x, ndim = size(x, 1) rows of box used) lies in the closed box, which holds
  !! every point the rank's part owns and every point touching a node it owns
  !! (decomposition_m local_part_build takes no other rows); every element's without a
  !! box. keep (ne) and t%ptr (ne + 1) over rows of size(cells, 1) entries each.
  subroutine element_rows(t, x, cells, keep, box)
    type(solid_tables_t), intent(inout) :: t
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: cells(:, :)
    logical, allocatable, intent(out) :: keep(:)
    real(wp), intent(in), optional :: box(:, :)
    integer :: e, ne, nd, nv, k
    ne = size(cells, 2)
    nd = size(x, 1)
    nv = size(cells, 1)
    allocate(keep(ne))
    keep = .true.
    if (present(box)) then
      do e = 1, ne
        keep(e) = in_box(t%xq(:, e))
        do k = 1, nv
          keep(e) = keep(e) .or. in_box(x(:, cells(k, e)))
        end do
      end do
    end if
    if (allocated(t%ptr)) deallocate(t%ptr)
    allocate(t%ptr(ne + 1))
    t%ptr(1) = 1
    do e = 1, ne
      t%ptr(e + 1) = t%ptr(e) + merge(nv, 0, keep(e))
    end do
  contains
    pure logical function in_box(y)
      real(wp), intent(in) :: y(:)
      in_box = all(y(1:nd) >= box(1:nd, 1)) .and. all(y(1:nd) <= box(1:nd, 2))
    end function in_box
  end subroutine element_rows

  !> The end of an element builder's tables (cst4_m, tet4_m), once masses and weights are
  !! in: the position table N_I(X_J) is the identity (nodal interpolation: eq. 99), the
  !! totals, the transpose.
  subroutine tables_finish_elements(t, transpose)
    type(solid_tables_t), intent(inout) :: t
    !> build the transpose (default; .false.: a rank's rows, transposed after the split,
    !! and position rows only at the nodes those rows touch: the rank's region, not the
    !! whole mesh's nodes, decomposition_m region_of)
    logical, intent(in), optional :: transpose
    logical, allocatable :: has(:)
    integer :: i, j
    logical :: rows
    rows = .false.
    if (present(transpose)) rows = .not. transpose
    allocate(has(t%np))
    has = .not. rows
    if (rows) has(t%nbr) = .true.
    allocate(t%pptr(t%np + 1), t%pnbr(count(has)), t%pn(t%dims%npos, count(has)))
    t%pptr(1) = 1
    j = 0
    do i = 1, t%np
      if (has(i)) then
        j = j + 1
        t%pnbr(j) = i
      end if
      t%pptr(i + 1) = j + 1
    end do
    t%pn = 1.0_wp
    t%total_mass = sum(t%mass)
    t%total_volume = sum(t%wgt)
    if (rows) return
    call tables_transpose(t)
  end subroutine tables_finish_elements

  !> For each particle, the entries (and their points) that involve it, and the values of
  !! the entries in that order. Called once g, h and gs are final. In 3D the force gather
  !! (tl_kinematics3d_m) reads tq, tg and tgs only, and h vanishes: the values are copied
  !! as the transpose is filled, without tent and th (12 B an entry, about 1.4 kB a 3D
  !! particle, at the set-up's peak and in the time loop).
  subroutine tables_transpose(t)
    type(solid_tables_t), intent(inout) :: t
    integer, allocatable :: fill(:)
    integer :: q, e, i, k, nnz
    logical :: full, with_gs
    nnz = size(t%nbr)
    full = t%dims%ndim /= 3
    allocate(t%tptr(t%np + 1), t%tq(nnz), fill(t%np))
    fill = 0
    do e = 1, nnz
      fill(t%nbr(e)) = fill(t%nbr(e)) + 1
    end do
    t%tptr(1) = 1
    do i = 1, t%np
      t%tptr(i + 1) = t%tptr(i) + fill(i)
    end do
    fill = 0
    if (full) then
      allocate(t%tent(nnz))
      do q = 1, t%nq
        do e = t%ptr(q), t%ptr(q + 1) - 1
          i = t%nbr(e)
          t%tent(t%tptr(i) + fill(i)) = e
          t%tq(t%tptr(i) + fill(i)) = q
          fill(i) = fill(i) + 1
        end do
      end do
      call tables_transpose_values(t)
      return
    end if
    with_gs = allocated(t%gs)
    if (with_gs) with_gs = size(t%gs, 2) == size(t%g, 2)
    allocate(t%tg(size(t%g, 1), nnz))
    if (with_gs) allocate(t%tgs(size(t%gs, 1), nnz))
    do q = 1, t%nq
      do e = t%ptr(q), t%ptr(q + 1) - 1
        i = t%nbr(e)
        k = t%tptr(i) + fill(i)
        t%tq(k) = q
        t%tg(:, k) = t%g(:, e)
        if (with_gs) t%tgs(:, k) = t%gs(:, e)
        fill(i) = fill(i) + 1
      end do
    end do
  end subroutine tables_transpose

  !> Copies of g, h (and gs when the tables have them) in the transpose's order. The force
  !! gather visits the entries particle by particle; reading g through tent jumps across
  !! the whole table (tens of MB, beyond the caches) at every entry, reading tg streams it:
  !! the internal-force pass fell from 270 to about 100 ns per particle-step on the free-bar
  !! benchmark (doc/benchmarks.md, per-pass model). Same values, same order of the sums:
  !! the forces are the same to the bit. Needs tent (not built in 3D: tables_transpose).
  subroutine tables_transpose_values(t)
    type(solid_tables_t), intent(inout) :: t
    integer :: k, e, nnz
    logical :: with_gs
    nnz = size(t%tent)
    with_gs = allocated(t%gs)
    if (with_gs) with_gs = size(t%gs, 2) == size(t%g, 2)
    allocate(t%tg(size(t%g, 1), nnz), t%th(nnz))
    if (with_gs) allocate(t%tgs(size(t%gs, 1), nnz))
    do k = 1, nnz
      e = t%tent(k)
      t%tg(:, k) = t%g(:, e)
      t%th(k) = t%h(e)
      if (with_gs) t%tgs(:, k) = t%gs(:, e)
    end do
  end subroutine tables_transpose_values
end module solid_tables_m
