!> A conventional node-to-segment contact search (Benson and Hallquist's bucket sort), the
!! kind of detector the paper sets det(M) against (Section 2), behind the same contact
!! interface (contact_pair_m, &contact detector = 'node_to_segment').
!!
!! The master's surface segments (master_surface_t, counter-clockwise polylines) are bucket
!! sorted by their midpoints into a uniform grid of square cells as wide as the longest
!! segment, held as linked lists (head(cell), next(segment)). A slave point's closest
!! segment is then found by scanning rings of cells around the point's cell outwards, and
!! stopping once no unscanned cell can hold a closer segment (or one within the capture
!! distance): the 3 x 3 neighbouring buckets of the classical search in the common case.
!! The closest-segment projection gives the gap g = (x_s - x_a) . n of eq. (89), with the
!! same closest-segment rule as the det(M) path (contact_m: closest_segment_update), so both
!! detectors measure the same gap; a point is flagged when g < 0.
!!
!! A rigid master's buckets are built once; a deformable master's are rebuilt (O(segments),
!! no allocation) whenever its surface moves. The cell array is allocated at set-up with
!! room for the master's box to grow fourfold in area; beyond that the cells are widened.
module contact_nts_m
  use kinds_m, only: wp
  use contact_m, only: master_surface_t, closest_segment_update, surface_projection
  implicit none
  private
  public :: nts_buckets_t, nts_build, nts_update, nts_gap

  !> Room for the grid of a deformable master to grow over the run, as a multiple of the
  !! initial cell count (more cells are made by widening them, which is always correct).
  integer, parameter :: cell_room = 4
  !> Points are placed into cells through an integer cell index: coordinates farther than
  !! this many cells from the grid are clamped (they are beyond any capture distance).
  real(wp), parameter :: far_cells = 1.0e6_wp

  !> Buckets of a master's segments by midpoint.
  type :: nts_buckets_t
    real(wp) :: lo(2) = 0.0_wp      !< grid origin (m)
    real(wp) :: cell = 1.0_wp       !< cell width, >= the longest segment (m)
    real(wp) :: half_len = 0.0_wp   !< half the longest segment: reach from a midpoint (m)
    !> Search radius (m): the longest segment, so the classical neighbouring buckets
    !! suffice; a point farther than this from every segment is not in contact.
    real(wp) :: capture = 0.0_wp
    integer :: nc(2) = 1            !< cells per direction
    integer, allocatable :: head(:) !< first segment of each cell (0: empty)
    integer, allocatable :: next(:) !< next segment in the same cell (0: last)
  end type nts_buckets_t

contains

  !> Buckets for the surface s, with room for a deformable master's grid to grow.
  subroutine nts_build(bk, s)
    type(nts_buckets_t), intent(out) :: bk
    type(master_surface_t), intent(in) :: s
    allocate(bk%next(max(s%nseg, 1)))
    call grid_for(bk, s)
    allocate(bk%head(max(cell_room*product(bk%nc), 16)))
    call nts_update(bk, s)
  end subroutine nts_build

  !> Re-sort the segments after the surface s moved (no allocation).
  subroutine nts_update(bk, s)
    type(nts_buckets_t), intent(inout) :: bk
    type(master_surface_t), intent(in) :: s
    integer :: j, c
    call grid_for(bk, s)
    do while (product(bk%nc) > size(bk%head))
      bk%cell = 2.0_wp*bk%cell
      call cell_counts(bk, s)
    end do
    bk%head(1:product(bk%nc)) = 0
    do j = 1, s%nseg
      c = cell_id(bk, s%mid(:, j))
      bk%next(j) = bk%head(c)
      bk%head(c) = j
    end do
  end subroutine nts_update

  !> Cell width and grid over the segment midpoints of s.
  subroutine grid_for(bk, s)
    type(nts_buckets_t), intent(inout) :: bk
    type(master_surface_t), intent(in) :: s
    integer :: j
    bk%half_len = 0.0_wp
    do j = 1, s%nseg
      bk%half_len = max(bk%half_len, 0.5_wp*norm2(s%b(:, j) - s%a(:, j)))
    end do
    bk%half_len = max(bk%half_len, tiny(1.0_wp))
    bk%cell = 2.0_wp*bk%half_len
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
    bk%lo = minval(s%mid, dim=2)
    bk%nc = int((maxval(s%mid, dim=2) - bk%lo)/bk%cell) + 1
  end subroutine cell_counts

  !> Cell index per direction of p, zero-based, not clamped to the grid.
  pure function cell_ij(bk, p) result(ij)
    type(nts_buckets_t), intent(in) :: bk
    real(wp), intent(in) :: p(2)
    integer :: ij(2)
    ij = floor(max(-far_cells, min(far_cells, (p - bk%lo)/bk%cell)))
  end function cell_ij

  !> Flat cell id (1-based) of a point of the grid.
  pure integer function cell_id(bk, p) result(c)
    type(nts_buckets_t), intent(in) :: bk
    real(wp), intent(in) :: p(2)
    integer :: ij(2)
    ij = min(bk%nc - 1, max(0, cell_ij(bk, p)))
    c = 1 + ij(1) + bk%nc(1)*ij(2)
  end function cell_id

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
    real(wp) :: dbest, gbest
    jbest = 0
    dbest = huge(1.0_wp)
    gbest = -huge(1.0_wp)
    ij = cell_ij(bk, p)
    k = 0
    do
      ! cells k rings out lie at least (k - 1) cells from p, and their segments reach
      ! half_len from their midpoints: nothing there can be closer, or within capture; the
      ! margin, 1e-9 cells, covers the corner tie of closest_segment_update (1e-9 of the
      ! largest segment extent, at most a cell)
      if (real(k - 1, wp)*bk%cell - bk%half_len > min(dbest, capture) + 1.0e-9_wp*bk%cell) &
        exit
      do j = ij(2) - k, ij(2) + k
        if (j < 0 .or. j >= bk%nc(2)) cycle
        ! the full row on the ring's top and bottom, its two ends elsewhere
        istep = merge(1, max(2*k, 1), abs(j - ij(2)) == k)
        do i = ij(1) - k, ij(1) + k, istep
          if (i < 0 .or. i >= bk%nc(1)) cycle
          q = bk%head(1 + i + bk%nc(1)*j)
          do while (q > 0)
            call closest_segment_update(s, q, p, jbest, dbest, gbest)
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
