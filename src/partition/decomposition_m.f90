!> Domain decomposition of a solid for distributed-memory runs (issue 12; doc/parallel.md):
!! the nodes and integration points of a solid's tables split among nparts ranks by a
!! recursive coordinate bisection of the reference configuration, and each rank's local
!! tables.
!!
!! A rank owns the nodes and the points inside its box of the bisection tree (the same cuts
!! for both). Its local tables hold
!!   - its points, and the ghost points: the other ranks' points that touch one of its nodes
!!     (their stresses P come from their owners: halo exchange of P);
!!   - the nodes of its points, its own nodes, the nodes of the position table rows of its
!!     own nodes (eq. 65: a particle's physical position needs its neighbours'
!!     coefficients), and the particles whose rows hold one of its nodes (eq. 98 spreads
!!     their contact forces onto it); those it does not own are its ghost nodes (their
!!     values come from their owners: halo exchange of d, v, a, and contact point forces).
!! Both are numbered in the global order. So a rank's F at its points sums the same entries
!! in the same order as the serial run, and the force gather at one of its nodes (eq. 72,
!! over the transpose) visits the same points in the same order: the forces at owned nodes
!! equal the serial ones to the bit, whatever the number of ranks (checked by
!! tests/unit/partition/test_decomposition.pf on emulated ranks). A ghost point's row keeps
!! only the entries of its local nodes: it is never evaluated locally.
module decomposition_m
  use kinds_m, only: wp, i64
  use rank_comm_m, only: rank_comm_t, single_rank_t
  use body_m, only: body_t
  use solid_tables_m, only: solid_tables_t, tables_transpose, tables_copy_scalars, &
    tables_move
  implicit none
  private
  public :: rcb_tree_t, rcb_build, rcb_build_ranks, rcb_part, rcb_box, local_part_t, &
    local_part_build, local_part_sets, local_part_rows, region_of, region_rows

  !> The bisection tree: node k (1 the root) is a leaf of part part(k), or cuts along axis
  !! axis(k) at cut(k), with the points below the cut in child lo(k), the others in hi(k).
  type :: rcb_tree_t
    integer :: nparts = 1
    integer :: nt = 0
    integer, allocatable :: part(:), axis(:), lo(:), hi(:)
    real(wp), allocatable :: cut(:)
  end type rcb_tree_t

  !> One rank's share of a solid (global numbers 1-based, ascending).
  type :: local_part_t
    integer :: rank = 0
    integer :: nq_own = 0, np_own = 0      !< points and nodes it owns
    integer, allocatable :: qglob(:)       !< its local points' global numbers (nql)
    integer, allocatable :: nglob(:)       !< its local nodes' global numbers (npl)
    logical, allocatable :: own_point(:), own_node(:)   !< (nql), (npl)
    integer, allocatable :: q_owned(:), n_owned(:)       !< local numbers of the owned ones
    type(solid_tables_t) :: t              !< the local tables (global order)
  end type local_part_t

contains

  !> The bisection of the points x (ndim, n) into nparts parts (rcb_build_ranks on one
  !! rank: every point here).
  subroutine rcb_build(x, nparts, tree)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: nparts
    type(rcb_tree_t), intent(out) :: tree
    type(single_rank_t) :: one
    call rcb_build_ranks(x, nparts, one, tree)
  end subroutine rcb_build

  !> The bisection into nparts parts of the points that the ranks of comm share: x holds
  !! this rank's share (every point on exactly one rank, any share, none at all too). At
  !! each level the box is cut across its longest extent (the first of equal ones), at the
  !! coordinate that leaves floor(np/2)/np of its points below: halfway between the nlo-th
  !! and the nlo+1-th coordinate along that axis (points on the cut go above, so a lattice
  !! row is never split and the parts differ by up to a row; the cut decides for any point,
  !! also one not in the set). Every rank gets the same tree whatever the shares, while no
  !! rank holds more than its share: the extents are maxima over the ranks, and each cut's
  !! two order statistics are found by bisection over the coordinates' bit patterns,
  !! ordered as the numbers are (ordered_key: at most 65 counts summed over the ranks). The
  !! boxes of a level are cut together (their counts, extents and order statistics in one
  !! reduction each: some 67 reductions a level, log2(nparts) levels, rather than 67 a
  !! cut), and the tree is numbered depth first, its parts left to right, as a cut after
  !! cut would make it. A rank's work is its share's counts. Collective.
  subroutine rcb_build_ranks(x, nparts, comm, tree)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: nparts
    class(rank_comm_t), intent(inout) :: comm
    type(rcb_tree_t), intent(out) :: tree
    ! b: the tree as the levels make it (breadth first); npk: the parts each node makes
    type(rcb_tree_t) :: b
    integer, allocatable :: node_of(:), npk(:), cur(:), nxt(:), slot(:), ax(:)
    integer(i64), allocatable :: n(:), r(:, :)
    real(wp), allocatable :: mm(:), v(:, :), lim(:, :)
    integer :: i, j, k, nd, m, plo, next_part
    integer(i64) :: nlo
    nd = size(x, 1)
    call tree_empty(b, nparts)
    allocate(npk(2*nparts), slot(2*nparts))
    npk = 0
    npk(1) = nparts
    allocate(node_of(size(x, 2)))
    node_of = 1
    cur = [integer ::]
    if (nparts > 1) cur = [1]
    do while (size(cur) > 0)
      m = size(cur)
      slot = 0
      slot(cur) = [(j, j = 1, m)]
      ! each box's count and extremes (the smallest as the largest of the negatives: exact)
      allocate(n(m), mm(2*nd*m), ax(m), r(2, m), v(2, m), lim(2, m))
      n = 0
      mm = -huge(1.0_wp)
      do i = 1, size(x, 2)
        j = slot(node_of(i))
        if (j == 0) cycle
        n(j) = n(j) + 1
        associate (mj => mm(2*nd*(j - 1) + 1:2*nd*j))
          mj(1:nd) = max(mj(1:nd), x(:, i))
          mj(nd + 1:) = max(mj(nd + 1:), -x(:, i))
        end associate
      end do
      call comm%sum_i8(n)
      call comm%max_real(mm)
      ! each box's axis and the ranks of its cut's two order statistics (0: no cut inside)
      do j = 1, m
        associate (mj => mm(2*nd*(j - 1) + 1:2*nd*j))
          ax(j) = 1
          if (n(j) > 0) ax(j) = maxloc(mj(1:nd) - (-mj(nd + 1:)), dim=1)
          lim(:, j) = [-mj(nd + ax(j)), mj(ax(j))]
        end associate
        plo = npk(cur(j))/2
        nlo = (n(j)*plo)/npk(cur(j))
        r(:, j) = 0
        if (nlo > 0 .and. nlo < n(j)) r(:, j) = [nlo, nlo + 1]
      end do
      call level_statistics(x, node_of, slot, ax, r, lim, comm, v)
      ! the cuts, and the children (numbered breadth first here)
      nxt = [integer ::]
      do j = 1, m
        k = cur(j)
        plo = npk(k)/2
        nlo = (n(j)*plo)/npk(k)
        if (r(1, j) > 0) then
          b%cut(k) = 0.5_wp*(v(1, j) + v(2, j))
        else if (nlo == 0) then
          b%cut(k) = -huge(1.0_wp)
        else
          b%cut(k) = huge(1.0_wp)
        end if
        b%axis(k) = ax(j)
        b%lo(k) = b%nt + 1
        b%hi(k) = b%nt + 2
        b%nt = b%nt + 2
        npk(b%lo(k)) = plo
        npk(b%hi(k)) = npk(k) - plo
        if (plo > 1) nxt = [nxt, b%lo(k)]
        if (npk(k) - plo > 1) nxt = [nxt, b%hi(k)]
      end do
      do i = 1, size(x, 2)
        k = node_of(i)
        if (slot(k) == 0) cycle
        if (x(b%axis(k), i) < b%cut(k)) then
          node_of(i) = b%lo(k)
        else
          node_of(i) = b%hi(k)
        end if
      end do
      deallocate(n, mm, ax, r, v, lim)
      call move_alloc(nxt, cur)
    end do
    ! numbered depth first, the parts left to right
    call tree_empty(tree, nparts)
    next_part = 1
    call renumber(1, 1)
  contains
    !> Node kb of b as node kt of the tree, its children after it.
    recursive subroutine renumber(kb, kt)
      integer, intent(in) :: kb, kt
      if (npk(kb) == 1) then
        tree%part(kt) = next_part
        next_part = next_part + 1
        return
      end if
      tree%axis(kt) = b%axis(kb)
      tree%cut(kt) = b%cut(kb)
      tree%lo(kt) = tree%nt + 1
      tree%hi(kt) = tree%nt + 2
      tree%nt = tree%nt + 2
      call renumber(b%lo(kb), tree%lo(kt))
      call renumber(b%hi(kb), tree%hi(kt))
    end subroutine renumber
  end subroutine rcb_build_ranks

  !> A tree of nparts parts with its root only (room for its 2 nparts - 1 nodes).
  subroutine tree_empty(t, nparts)
    type(rcb_tree_t), intent(out) :: t
    integer, intent(in) :: nparts
    t%nparts = nparts
    allocate(t%part(2*nparts), t%axis(2*nparts), t%lo(2*nparts), t%hi(2*nparts), &
      t%cut(2*nparts))
    t%part = 0
    t%axis = 0
    t%lo = 0
    t%hi = 0
    t%cut = 0.0_wp
    t%nt = 1
  end subroutine tree_empty

  !> v(:, j): the r(1, j)-th and r(2, j)-th smallest (from 1) of the coordinates along
  !! axis ax(j) of the points the ranks of comm hold in box j of a level (node_of(i): the
  !! node of point i, slot(node): its box, 0 for none), exactly, as values one of them
  !! holds (a zero as +0); all of them within lim(:, j). Each value's bit pattern is made
  !! an integer that orders as the values do (ordered_key); for every box at once the
  !! smallest key K with at least r keys <= K is bisected between the keys of lim, the
  !! counts summed over the ranks each halving. Boxes with r(:, j) = 0 have no cut.
  !! Collective.
  subroutine level_statistics(x, node_of, slot, ax, r, lim, comm, v)
    real(wp), intent(in) :: x(:, :), lim(:, :)
    integer, intent(in) :: node_of(:), slot(:), ax(:)
    integer(i64), intent(in) :: r(:, :)
    class(rank_comm_t), intent(inout) :: comm
    real(wp), intent(out) :: v(:, :)
    ! (on the heap: a rank's share may be millions of values)
    integer(i64), allocatable :: key(:), klo(:, :), khi(:, :), mid(:, :), c(:, :), cs(:)
    integer :: i, j, l, m
    m = size(ax)
    allocate(key(size(x, 2)), klo(2, m), khi(2, m), mid(2, m), c(2, m))
    key = 0
    do i = 1, size(x, 2)
      j = slot(node_of(i))
      if (j == 0) cycle
      key(i) = ordered_key(x(ax(j), i))
    end do
    klo = 0
    khi = 0
    do j = 1, m
      if (r(1, j) == 0) cycle
      klo(:, j) = ordered_key(lim(1, j))
      khi(:, j) = ordered_key(lim(2, j))
    end do
    do while (any(klo < khi))
      ! the floor of the midpoint, without overflow
      mid = shifta(klo, 1) + shifta(khi, 1) + iand(iand(klo, khi), 1_i64)
      c = 0
      do i = 1, size(x, 2)
        j = slot(node_of(i))
        if (j == 0) cycle
        do l = 1, 2
          if (key(i) <= mid(l, j)) c(l, j) = c(l, j) + 1
        end do
      end do
      cs = reshape(c, [2*m])
      call comm%sum_i8(cs)
      c = reshape(cs, [2, m])
      do j = 1, m
        do l = 1, 2
          if (klo(l, j) >= khi(l, j)) cycle
          if (c(l, j) >= r(l, j)) then
            khi(l, j) = mid(l, j)
          else
            klo(l, j) = mid(l, j) + 1
          end if
        end do
      end do
    end do
    do j = 1, m
      do l = 1, 2
        v(l, j) = key_value(klo(l, j))
      end do
    end do
  end subroutine level_statistics

  !> An integer that orders as the real values do (a zero of either sign is 0): the bit
  !! pattern of a value >= 0, minus one less the magnitude's bits of a negative one.
  pure integer(i64) function ordered_key(a) result(key)
    real(wp), intent(in) :: a
    integer(i64) :: bits
    bits = transfer(a, 0_i64)
    if (a == 0.0_wp) bits = 0_i64
    key = bits
    if (bits < 0) key = -iand(bits, huge(0_i64)) - 1_i64
  end function ordered_key

  !> The value whose ordered_key is key.
  pure real(wp) function key_value(key) result(a)
    integer(i64), intent(in) :: key
    integer(i64) :: bits
    bits = key
    if (key < 0) bits = ior(-(key + 1_i64), ibset(0_i64, 63))
    a = transfer(bits, 1.0_wp)
  end function key_value

  !> The part of the tree's box that holds point xp.
  pure integer function rcb_part(tree, xp) result(p)
    type(rcb_tree_t), intent(in) :: tree
    real(wp), intent(in) :: xp(:)
    integer :: k
    k = 1
    do while (tree%part(k) == 0)
      if (xp(tree%axis(k)) < tree%cut(k)) then
        k = tree%lo(k)
      else
        k = tree%hi(k)
      end if
    end do
    p = tree%part(k)
  end function rcb_part

  !> The box of part p of the tree: lo(:) <= x < hi(:) for every point x rcb_part puts in
  !! p (a side with no cut is at -huge or huge).
  subroutine rcb_box(tree, p, lo, hi)
    type(rcb_tree_t), intent(in) :: tree
    integer, intent(in) :: p
    real(wp), intent(out) :: lo(:), hi(:)
    logical :: found
    lo = -huge(1.0_wp)
    hi = huge(1.0_wp)
    found = walk(1)
  contains
    !> Is p's leaf below tree node k? On the way back, each cut on its path bounds the box.
    recursive logical function walk(k) result(below)
      integer, intent(in) :: k
      if (tree%part(k) /= 0) then
        below = tree%part(k) == p
        return
      end if
      below = walk(tree%lo(k))
      if (below) then
        hi(tree%axis(k)) = min(hi(tree%axis(k)), tree%cut(k))
        return
      end if
      below = walk(tree%hi(k))
      if (below) lo(tree%axis(k)) = max(lo(tree%axis(k)), tree%cut(k))
    end function walk
  end subroutine rcb_box

  !> Rank r's local share of the tables t, with node_part (np) and point_part (nq) the
  !! owners of t's nodes and points (see the module's header). transpose .false.: without
  !! the local tables' transpose (the caller frees t first, then transposes).
  subroutine local_part_build(t, node_part, point_part, r, lp, transpose)
    type(solid_tables_t), intent(inout) :: t
    integer, intent(in) :: node_part(:), point_part(:), r
    type(local_part_t), intent(out) :: lp
    logical, intent(in), optional :: transpose
    call local_part_sets(t, node_part, point_part, r, lp)
    call local_part_rows(t, lp, transpose)
  end subroutine local_part_build

  !> The sets of rank r's share of the tables t (local_part_build): its local points and
  !! nodes by global number, which of them it owns; no rows yet (local_part_rows).
  subroutine local_part_sets(t, node_part, point_part, r, lp)
    type(solid_tables_t), intent(in) :: t
    integer, intent(in) :: node_part(:), point_part(:), r
    type(local_part_t), intent(out) :: lp
    logical, allocatable :: lq(:), ln(:)
    integer :: q, e, i, j, k, nql, npl
    logical :: with_pos
    lp%rank = r
    allocate(lq(t%nq), ln(t%np))
    lq = point_part == r
    ln = node_part == r
    ! ghost points: the others' points touching an owned node
    do q = 1, t%nq
      if (lq(q)) cycle
      do e = t%ptr(q), t%ptr(q + 1) - 1
        if (node_part(t%nbr(e)) == r) then
          lq(q) = .true.
          exit
        end if
      end do
    end do
    ! local nodes: owned, those of owned points, the position neighbours of owned nodes
    do q = 1, t%nq
      if (point_part(q) /= r) cycle
      ln(t%nbr(t%ptr(q):t%ptr(q + 1) - 1)) = .true.
    end do
    with_pos = allocated(t%pptr) .and. .not. t%interpolating
    if (with_pos) then
      do j = 1, t%np
        if (node_part(j) == r) then
          ln(t%pnbr(t%pptr(j):t%pptr(j + 1) - 1)) = .true.
        else if (any(node_part(t%pnbr(t%pptr(j):t%pptr(j + 1) - 1)) == r)) then
          ! a particle whose position involves an owned node: its contact force is spread
          ! onto that node by eq. (98)
          ln(j) = .true.
        end if
      end do
    end if
    lp%qglob = pack([(q, q = 1, t%nq)], lq)
    lp%nglob = pack([(i, i = 1, t%np)], ln)
    nql = size(lp%qglob)
    npl = size(lp%nglob)
    lp%own_point = point_part(lp%qglob) == r
    lp%own_node = node_part(lp%nglob) == r
    lp%nq_own = count(lp%own_point)
    lp%np_own = count(lp%own_node)
    lp%q_owned = pack([(k, k = 1, nql)], lp%own_point)
    lp%n_owned = pack([(k, k = 1, npl)], lp%own_node)
  end subroutine local_part_sets

  !> The local tables of rank lp%rank's share of t (local_part_build), its sets made
  !! (local_part_sets). release: t's arrays are freed as their rows are copied, each array
  !! once the part's copy of it is made (t keeps its scalars), so that the part's rows and
  !! t's are never held whole together (mpi_domain_m make_part: the split's peak).
  subroutine local_part_rows(t, lp, transpose, release)
    type(solid_tables_t), intent(inout) :: t
    type(local_part_t), intent(inout) :: lp
    logical, intent(in), optional :: transpose, release
    integer, allocatable :: nloc(:), src(:)
    integer :: q, e, j, k, nql, npl, nnz
    logical :: with_gs, free
    free = .false.
    if (present(release)) free = release
    nql = size(lp%qglob)
    npl = size(lp%nglob)
    allocate(nloc(t%np))
    nloc = 0
    nloc(lp%nglob) = [(k, k = 1, npl)]
    ! the local tables: rows of the local points over their local nodes, in global order;
    ! src: each local entry's entry of t
    nnz = 0
    do k = 1, nql
      q = lp%qglob(k)
      nnz = nnz + count(nloc(t%nbr(t%ptr(q):t%ptr(q + 1) - 1)) > 0)
    end do
    with_gs = allocated(t%gs)
    if (with_gs) with_gs = size(t%gs, 2) == size(t%g, 2)
    associate (u => lp%t)
      call tables_copy_scalars(t, u)
      u%np = npl
      u%nq = nql
      allocate(u%ptr(nql + 1), u%nbr(nnz), src(nnz))
      u%ptr(1) = 1
      nnz = 0
      do k = 1, nql
        q = lp%qglob(k)
        do e = t%ptr(q), t%ptr(q + 1) - 1
          if (nloc(t%nbr(e)) == 0) cycle
          nnz = nnz + 1
          u%nbr(nnz) = nloc(t%nbr(e))
          src(nnz) = e
        end do
        u%ptr(k + 1) = nnz + 1
      end do
      u%xq = t%xq(:, lp%qglob)
      u%owner = t%owner(lp%qglob)
      ! (a ghost point whose owner node is not local: -1; 0 is a point without an owner)
      where (u%owner > 0) u%owner = nloc(u%owner)
      where (u%owner == 0 .and. t%owner(lp%qglob) > 0) u%owner = -1
      u%wgt = t%wgt(lp%qglob)
      if (allocated(t%ws)) u%ws = t%ws(:, lp%qglob)
      u%mass = t%mass(lp%nglob)
      u%fix1 = t%fix1(lp%nglob)
      ! position table rows of the local nodes over their local neighbours (exact for the
      ! owned nodes, whose neighbours are all local)
      if (allocated(t%pptr)) then
        allocate(u%pptr(npl + 1))
        u%pptr(1) = 1
        nnz = 0
        do k = 1, npl
          j = lp%nglob(k)
          nnz = nnz + count(nloc(t%pnbr(t%pptr(j):t%pptr(j + 1) - 1)) > 0)
          u%pptr(k + 1) = nnz + 1
        end do
        allocate(u%pnbr(nnz), u%pn(t%dims%npos, nnz))
        nnz = 0
        do k = 1, npl
          j = lp%nglob(k)
          do e = t%pptr(j), t%pptr(j + 1) - 1
            if (nloc(t%pnbr(e)) == 0) cycle
            nnz = nnz + 1
            u%pnbr(nnz) = nloc(t%pnbr(e))
            u%pn(:, nnz) = t%pn(:, e)
          end do
        end do
      end if
      if (free) call free_rows(t)
      ! the entries' values, one array at a time
      u%g = t%g(:, src)
      if (free) deallocate(t%g)
      u%h = t%h(src)
      if (free) deallocate(t%h)
      if (with_gs) then
        u%gs = t%gs(:, src)
        if (free) deallocate(t%gs)
      end if
    end associate
    if (present(transpose)) then
      if (.not. transpose) return
    end if
    call tables_transpose(lp%t)
  end subroutine local_part_rows

  !> The region of a rank's tables t of body b with its box (dynamic_setup_m region_box):
  !! every particle a kept row touches (the points' nodes and owners, the position rows'
  !! particles and their neighbours) or the box holds (its part's own nodes), ascending:
  !! every node of the part the split will make from these rows (local_part_sets).
  subroutine region_of(t, b, box, rows)
    type(solid_tables_t), intent(in) :: t
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: box(3, 2)
    integer, allocatable, intent(out) :: rows(:)
    logical, allocatable :: mark(:)
    integer :: q, j, i, nd
    nd = b%ndim
    allocate(mark(b%np))
    mark = .false.
    do q = 1, t%nq
      if (t%ptr(q + 1) == t%ptr(q)) cycle
      mark(t%nbr(t%ptr(q):t%ptr(q + 1) - 1)) = .true.
      if (t%owner(q) > 0) mark(t%owner(q)) = .true.
    end do
    if (allocated(t%pptr)) then
      do j = 1, t%np
        if (t%pptr(j + 1) == t%pptr(j)) cycle
        mark(j) = .true.
        mark(t%pnbr(t%pptr(j):t%pptr(j + 1) - 1)) = .true.
      end do
    end if
    do i = 1, b%np
      if (all(b%x(:, i) >= box(1:nd, 1)) .and. all(b%x(:, i) <= box(1:nd, 2))) &
        mark(i) = .true.
    end do
    rows = pack([(i, i = 1, b%np)], mark)
  end subroutine region_of

  !> Tables t (rows numbered over the whole solid) renumbered in place over nodes (ascending
  !! node numbers) and the points with a row (ascending, returned in points): a rank's
  !! region (dynamic_setup_m), whose rows hold only its nodes, so that every entry stays,
  !! in the same order: the entries' values (g, h, gs, pn) are kept as they are, not
  !! copied; the points' and nodes' arrays are taken at the region's; the rows' node
  !! numbers (nbr, pnbr, owner) become places in nodes. ok: .false. when a row touches a
  !! node outside nodes, or a node outside nodes has a position row (t is then not
  !! usable).
  subroutine region_rows(t, nodes, points, ok)
    type(solid_tables_t), intent(inout) :: t
    integer, intent(in) :: nodes(:)
    integer, allocatable, intent(out) :: points(:)
    logical, intent(out) :: ok
    integer, allocatable :: nloc(:), ptr(:)
    integer :: q, k, npl, nql
    npl = size(nodes)
    allocate(nloc(t%np))
    nloc = 0
    nloc(nodes) = [(k, k = 1, npl)]
    points = pack([(q, q = 1, t%nq)], t%ptr(2:t%nq + 1) > t%ptr(1:t%nq))
    nql = size(points)
    ! every entry's node in the region, every kept point's owner too
    ok = all(nloc(t%nbr) > 0)
    if (ok) ok = all(t%owner(points) >= 0)
    if (ok) ok = all(nloc(pack(t%owner(points), t%owner(points) > 0)) > 0)
    if (ok .and. allocated(t%pptr)) then
      ok = all(nloc(t%pnbr) > 0)
      ! (a position row of a node outside the region would be dropped)
      if (ok) ok = t%pptr(t%np + 1) - t%pptr(1) == &
        sum(t%pptr(nodes + 1) - t%pptr(nodes))
    end if
    if (.not. ok) return
    ! (a transpose over the whole numbering, if a builder made one: the split makes the
    ! part's)
    if (allocated(t%tptr)) deallocate(t%tptr)
    if (allocated(t%tent)) deallocate(t%tent)
    if (allocated(t%tq)) deallocate(t%tq)
    if (allocated(t%tg)) deallocate(t%tg)
    if (allocated(t%th)) deallocate(t%th)
    if (allocated(t%tgs)) deallocate(t%tgs)
    ptr = rows_at(t%ptr, points)
    call move_alloc(ptr, t%ptr)
    t%nbr = nloc(t%nbr)
    t%xq = t%xq(:, points)
    t%owner = t%owner(points)
    where (t%owner > 0) t%owner = nloc(t%owner)
    t%wgt = t%wgt(points)
    if (allocated(t%ws)) t%ws = t%ws(:, points)
    t%mass = t%mass(nodes)
    t%fix1 = t%fix1(nodes)
    if (allocated(t%pptr)) then
      ptr = rows_at(t%pptr, nodes)
      call move_alloc(ptr, t%pptr)
      t%pnbr = nloc(t%pnbr)
    end if
    t%np = npl
    t%nq = nql

  contains

    !> The CSR pointer of the rows at(:) of the pointer p, in that order.
    pure function rows_at(p, at) result(r)
      integer, intent(in) :: p(:), at(:)
      integer, allocatable :: r(:)
      integer :: i
      allocate(r(size(at) + 1))
      r(1) = 1
      do i = 1, size(at)
        r(i + 1) = r(i) + p(at(i) + 1) - p(at(i))
      end do
    end function rows_at
  end subroutine region_rows

  !> Tables t without their rows' structure and their arrays over points and nodes (what
  !! local_part_rows has copied before the entries' values): those values stay.
  subroutine free_rows(t)
    type(solid_tables_t), intent(inout) :: t
    type(solid_tables_t) :: kept, gone
    call move_alloc(t%g, kept%g)
    call move_alloc(t%h, kept%h)
    call move_alloc(t%gs, kept%gs)
    call tables_move(t, gone)
    call move_alloc(kept%g, t%g)
    call move_alloc(kept%h, t%h)
    call move_alloc(kept%gs, t%gs)
  end subroutine free_rows
end module decomposition_m
