!> A conventional node-to-segment contact search (Benson and Hallquist's bucket sort), the
!! kind of detector the paper sets det(M) against (Section 2), behind the same contact
!! interface (contact_pair_m, &contact detector = 'node_to_segment').
!!
!! The master's surface segments (master_surface_t, counter-clockwise polylines) are bucket
!! sorted into a uniform grid of square cells as wide as the mean segment: each segment is
!! entered in every cell its bounding box overlaps, in linked lists (head(cell),
!! next(entry), OpenRadioss style), so a long segment beside short ones (the Taylor
!! target's 2 mm sides beside its 0.16 mm top) neither widens every cell nor hides from a
!! query. A slave point's closest segment is found by scanning rings of cells around the
!! point's cell outwards, stopping once no unscanned cell can hold a closer segment or one
!! within the capture distance of one cell: the 3 x 3 neighbouring buckets of the
!! classical search. The closest-segment projection gives the gap g = (x_s - x_a) . n of
!! eq. (89), with the det(M) path's own closest-segment rule (contact_m:
!! closest_segment_update), so both detectors measure the same gap; a point is flagged
!! when g < 0.
!!
!! A rigid master's buckets are built once; a deformable master's are rebuilt (O(entries),
!! no allocation) whenever its surface moves. The cell and entry arrays are allocated at
!! set-up with room for fourfold growth; beyond that the cells are widened.
module contact_nts_m
  use kinds_m, only: wp
  use contact_m, only: master_surface_t, closest_segment_update, surface_projection, &
    surface_tie_tol
  implicit none
  private
  public :: nts_buckets_t, nts_build, nts_update, nts_gap

  !> Room for the grid of a deformable master to grow over the run, as a multiple of the
  !! initial cell and entry counts (beyond it the cells widen, which is always correct).
  integer, parameter :: room = 4
  !> Points are placed into cells through an integer cell index: coordinates farther than
  !! this many cells from the grid are clamped (they are beyond any capture distance).
  real(wp), parameter :: far_cells = 1.0e6_wp

  !> Buckets of a master's segments.
  type :: nts_buckets_t
    real(wp) :: lo(2) = 0.0_wp      !< grid origin (m)
    real(wp) :: cell = 1.0_wp       !< cell width (m): the mean segment, or wider
    real(wp) :: mean_len = 0.0_wp   !< mean segment length (m)
    !> Search radius (m): one cell, the classical neighbouring buckets; a point farther
    !! than this from every segment is not in contact.
    real(wp) :: capture = 0.0_wp
    integer :: nc(2) = 1            !< cells per direction
    integer :: nentries = 0         !< segment entries in the cells
    integer, allocatable :: head(:) !< first entry of each cell (0: empty)
    integer, allocatable :: next(:) !< next entry in the same cell (0: last)
    integer, allocatable :: seg(:)  !< the segment of each entry
  end type nts_buckets_t

contains

  !> Buckets for the surface s, with room for a deformable master's grid to grow.
  subroutine nts_build(bk, s)
    type(nts_buckets_t), intent(out) :: bk
    type(master_surface_t), intent(in) :: s
    call grid_for(bk, s)
    allocate(bk%head(max(room*product(bk%nc), 16)))
    allocate(bk%next(max(room*entry_count(bk, s), 16)), bk%seg(max(room*entry_count(bk, &
      s), 16)))
    call nts_update(bk, s)
  end subroutine nts_build

  !> Re-sort the segments after the surface s moved (no allocation).
  subroutine nts_update(bk, s)
    type(nts_buckets_t), intent(inout) :: bk
    type(master_surface_t), intent(in) :: s
    integer :: j, c, ne, i0(2), i1(2), i, k
    call grid_for(bk, s)
    do while (product(bk%nc) > size(bk%head) .or. entry_count(bk, s) > size(bk%next))
      bk%cell = 2.0_wp*bk%cell
      call cell_counts(bk, s)
    end do
    bk%capture = bk%cell
    bk%head(1:product(bk%nc)) = 0
    ne = 0
    do j = 1, s%nseg
      call segment_cells(bk, s, j, i0, i1)
      do k = i0(2), i1(2)
        do i = i0(1), i1(1)
          c = 1 + i + bk%nc(1)*k
          ne = ne + 1
          bk%seg(ne) = j
          bk%next(ne) = bk%head(c)
          bk%head(c) = ne
        end do
      end do
    end do
    bk%nentries = ne
  end subroutine nts_update

  !> Cell width (the mean segment) and grid over the segments of s.
  subroutine grid_for(bk, s)
    type(nts_buckets_t), intent(inout) :: bk
    type(master_surface_t), intent(in) :: s
    integer :: j
    bk%mean_len = 0.0_wp
    do j = 1, s%nseg
      bk%mean_len = bk%mean_len + norm2(s%b(:, j) - s%a(:, j))
    end do
    bk%mean_len = max(bk%mean_len/real(max(s%nseg, 1), wp), tiny(1.0_wp))
    bk%cell = bk%mean_len
    bk%capture = bk%cell
    call cell_counts(bk, s)
  end subroutine grid_for

  subroutine cell_counts(bk, s)
    type(nts_buckets_t), intent(inout) :: bk
    type(master_surface_t), intent(in) :: s
    if (s%nseg == 0) then
      bk%lo = 0.0_wp
      bk%nc = 1
      return
    end if
    bk%lo = min(minval(s%a, dim=2), minval(s%b, dim=2))
    bk%nc = int((max(maxval(s%a, dim=2), maxval(s%b, dim=2)) - bk%lo)/bk%cell) + 1
  end subroutine cell_counts

  !> Entries the segments of s make in the grid of bk (cells their boxes overlap).
  integer function entry_count(bk, s) result(n)
    type(nts_buckets_t), intent(in) :: bk
    type(master_surface_t), intent(in) :: s
    integer :: j, i0(2), i1(2)
    n = 0
    do j = 1, s%nseg
      call segment_cells(bk, s, j, i0, i1)
      n = n + product(i1 - i0 + 1)
    end do
  end function entry_count

  !> The block of cells i0..i1 (zero-based) that segment j's bounding box overlaps.
  pure subroutine segment_cells(bk, s, j, i0, i1)
    type(nts_buckets_t), intent(in) :: bk
    type(master_surface_t), intent(in) :: s
    integer, intent(in) :: j
    integer, intent(out) :: i0(2), i1(2)
    i0 = min(bk%nc - 1, max(0, cell_ij(bk, min(s%a(:, j), s%b(:, j)))))
    i1 = min(bk%nc - 1, max(0, cell_ij(bk, max(s%a(:, j), s%b(:, j)))))
  end subroutine segment_cells

  !> Cell index per direction of p, zero-based, not clamped to the grid.
  pure function cell_ij(bk, p) result(ij)
    type(nts_buckets_t), intent(in) :: bk
    real(wp), intent(in) :: p(2)
    integer :: ij(2)
    ij = floor(max(-far_cells, min(far_cells, (p - bk%lo)/bk%cell)))
  end function cell_ij

  !> The closest segment of s to p found through the buckets bk, within the distance
  !! capture (m; bk%capture for the classical search), and the gap g = (p - a) . n to it
  !! (eq. 89), its outward normal and tangent, the segment and where p projects on it (0 at
  !! a, 1 at b). found is false when no segment is within capture.
  pure subroutine nts_gap(bk, s, p, capture, found, g, nrm, tng, seg, xi)
    type(nts_buckets_t), intent(in) :: bk
    type(master_surface_t), intent(in) :: s
    real(wp), intent(in) :: p(2), capture
    logical, intent(out) :: found
    real(wp), intent(out) :: g, nrm(2), tng(2)
    integer, intent(out), optional :: seg
    real(wp), intent(out), optional :: xi
    integer :: ij(2), k, i, j, jbest, q, istep
    real(wp) :: dbest, gbest, bound
    jbest = 0
    dbest = huge(1.0_wp)
    gbest = -huge(1.0_wp)
    ij = cell_ij(bk, p)
    k = 0
    do
      ! every point of a segment lies in a cell it is entered in, and cells k rings out lie
      ! at least (k - 1) cells from p: nothing there is closer (to within the corner tie of
      ! closest_segment_update), or within capture
      bound = real(k - 1, wp)*bk%cell
      if (bound > dbest + surface_tie_tol(s) .or. bound >= capture) exit
      do j = ij(2) - k, ij(2) + k
        if (j < 0 .or. j >= bk%nc(2)) cycle
        ! the full row on the ring's top and bottom, its two ends elsewhere
        istep = merge(1, max(2*k, 1), abs(j - ij(2)) == k)
        do i = ij(1) - k, ij(1) + k, istep
          if (i < 0 .or. i >= bk%nc(1)) cycle
          q = bk%head(1 + i + bk%nc(1)*j)
          do while (q > 0)
            call closest_segment_update(s, bk%seg(q), p, jbest, dbest, gbest)
            q = bk%next(q)
          end do
        end do
      end do
      ! the ring has covered the whole grid
      if (ij(1) - k <= 0 .and. ij(1) + k >= bk%nc(1) - 1 .and. ij(2) - k <= 0 .and. &
        ij(2) + k >= bk%nc(2) - 1) exit
      k = k + 1
    end do
    if (dbest > capture) jbest = 0
    call surface_projection(s, p, jbest, found, g, nrm, tng, seg, xi)
  end subroutine nts_gap
end module contact_nts_m
