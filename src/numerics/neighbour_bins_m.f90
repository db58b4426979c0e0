!> Uniform cell lists (bins) in 1D, 2D and 3D, stored in CSR form.
!!
!! Particles are counting-sorted into cells of size >= the largest support radius per
!! direction; cell c holds idx(start(c) : start(c+1)-1). A query box [p - r, p + r] overlaps a
!! clamped block of cells; points outside the grid get an empty block.
module neighbour_bins_m
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  implicit none
  private
  public :: bins_t, bins_build, bins_cell_block, bins_candidates, bins_brute_force
  public :: bins_cell_size, bins_block_runs, bins_block_run

  !> Cells cap: keeps memory bounded for very elongated or sparse clouds.
  integer, parameter :: max_cells = 16*1024*1024

  type :: bins_t
    integer :: ndim = 0
    integer :: np = 0
    real(wp) :: lo(3) = 0.0_wp       !< grid origin (m)
    real(wp) :: hi(3) = 0.0_wp       !< grid far corner (m)
    real(wp) :: cell(3) = 1.0_wp     !< cell size per direction (m)
    real(wp) :: inv_cell(3) = 1.0_wp
    integer :: nc(3) = 1             !< cells per direction
    !> a block of a larger grid (bins_build's grid_lo, grid_hi; distributed memory): the
    !! block's first cell in the grid, and the grid's cells per direction (nc, 0 otherwise)
    integer :: off(3) = 0
    integer :: ncg(3) = 1
    integer, allocatable :: start(:) !< CSR pointer, ncells + 1 used (may be longer)
    integer, allocatable :: idx(:)   !< particle ids sorted by cell
    integer, allocatable :: cid(:), fill(:)   !< work space of the build, kept for rebuilds
  end type bins_t

contains

  !> Build bins over x(ndim, np) with cells at least min_cell(ndim) wide (m). b may hold
  !! earlier bins: their arrays are reused when large enough, so re-binning a moving cloud
  !! every step allocates only when its grid outgrows every earlier one.
  !!
  !! With grid_lo and grid_hi (a box holding x; distributed memory), the cells are those the
  !! bins over every point in that box would have (its corner, the same cell size), and only
  !! the block of them that holds x is kept: a point falls in the same cell, and a query
  !! visits the points it holds in the same order, as in the bins over the whole cloud whose
  !! extremes grid_lo and grid_hi are (each rank's part of a contact master).
  subroutine bins_build(b, x, min_cell, err, grid_lo, grid_hi)
    type(bins_t), intent(inout) :: b
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(in) :: min_cell(:)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: grid_lo(:), grid_hi(:)
    integer :: ndim, np, i, c, ncell, d, last
    real(wp) :: ext(3)
    ndim = size(x, 1)
    np = size(x, 2)
    b%ndim = ndim
    b%np = np
    b%lo = 0.0_wp
    b%hi = 0.0_wp
    b%cell = 1.0_wp
    b%inv_cell = 1.0_wp
    b%nc = 1
    b%off = 0
    b%ncg = 1
    if (any(min_cell(1:ndim) <= 0.0_wp)) then
      call set_error(err, 'neighbour bins: cell size must be positive')
      return
    end if
    if (np == 0) then
      call ensure(b%start, 2)
      call ensure(b%idx, 0)
      b%start(1:2) = 1
      return
    end if
    if (present(grid_lo) .and. present(grid_hi)) then
      b%lo(1:ndim) = grid_lo(1:ndim)
      b%hi(1:ndim) = grid_hi(1:ndim)
    else
      ! (per direction: minval(x, dim=2) is a temporary of unknown size, a heap
      ! allocation at every rebuild, as a deforming master's at every step)
      do d = 1, ndim
        b%lo(d) = minval(x(d, :))
        b%hi(d) = maxval(x(d, :))
      end do
    end if
    ext = 0.0_wp
    ext(1:ndim) = b%hi(1:ndim) - b%lo(1:ndim)
    b%cell(1:ndim) = bins_cell_size(ext(1:ndim), min_cell(1:ndim))
    b%nc(1:ndim) = int(ext(1:ndim)/b%cell(1:ndim)) + 1
    b%inv_cell(1:ndim) = 1.0_wp/b%cell(1:ndim)
    b%ncg = b%nc
    if (present(grid_lo) .and. present(grid_hi)) then
      ! the block of the grid's cells that holds x
      do d = 1, ndim
        b%off(d) = grid_cell(b, d, minval(x(d, :)))
        last = grid_cell(b, d, maxval(x(d, :)))
        b%nc(d) = last - b%off(d) + 1
      end do
    end if
    ncell = product(b%nc)
    call ensure(b%cid, np)
    call ensure(b%fill, ncell)
    call ensure(b%start, ncell + 1)
    call ensure(b%idx, np)
    associate (cid => b%cid, fill => b%fill)
      fill(1:ncell) = 0
      do i = 1, np
        cid(i) = cell_of(b, x(:, i))
        fill(cid(i)) = fill(cid(i)) + 1
      end do
      b%start(1) = 1
      do c = 1, ncell
        b%start(c + 1) = b%start(c) + fill(c)
      end do
      fill(1:ncell) = 0
      do i = 1, np
        c = cid(i)
        b%idx(b%start(c) + fill(c)) = i
        fill(c) = fill(c) + 1
      end do
    end associate
  end subroutine bins_build

  !> The cell size of bins over a box of extent ext (ndim) with cells at least min_cell
  !! wide: min_cell, doubled until the cells number at most max_cells (m).
  pure function bins_cell_size(ext, min_cell) result(cell)
    real(wp), intent(in) :: ext(:), min_cell(:)
    real(wp) :: cell(size(ext))
    real(wp) :: ncells
    integer :: d
    cell = min_cell
    do
      ncells = 1.0_wp
      do d = 1, size(ext)
        ncells = ncells*real(int(ext(d)/cell(d)) + 1, wp)
      end do
      if (ncells <= max_cells) exit
      cell = 2.0_wp*cell
    end do
  end function bins_cell_size

  !> a allocated with at least n entries (reallocated, contents lost, only when shorter);
  !! start and idx may be longer than the bins use.
  subroutine ensure(a, n)
    integer, allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    if (allocated(a)) then
      if (size(a) >= n) return
      deallocate(a)
    end if
    allocate(a(max(n, 1)))
  end subroutine ensure

  !> Zero-based cell of the whole grid that coordinate z in direction d falls in.
  pure integer function grid_cell(b, d, z) result(i)
    type(bins_t), intent(in) :: b
    integer, intent(in) :: d
    real(wp), intent(in) :: z
    i = min(b%ncg(d) - 1, max(0, int((z - b%lo(d))*b%inv_cell(d))))
  end function grid_cell

  !> Flat cell id (1-based) of a point known to lie in the grid (in the block kept).
  pure integer function cell_of(b, p) result(c)
    type(bins_t), intent(in) :: b
    real(wp), intent(in) :: p(:)
    integer :: ijk(3), d
    ijk = 0
    do d = 1, b%ndim
      ijk(d) = min(b%nc(d) - 1, max(0, grid_cell(b, d, p(d)) - b%off(d)))
    end do
    c = 1 + ijk(1) + b%nc(1)*(ijk(2) + b%nc(2)*ijk(3))
  end function cell_of

  !> Zero-based cell index block [clo, chi] overlapped by the box [p - r, p + r].
  !! empty is true when the box misses the grid entirely.
  pure subroutine bins_cell_block(b, p, r, clo, chi, empty)
    type(bins_t), intent(in) :: b
    real(wp), intent(in) :: p(:), r(:)
    integer, intent(out) :: clo(3), chi(3)
    logical, intent(out) :: empty
    integer :: d
    real(wp) :: a, z
    clo = 0
    chi = 0
    empty = b%np == 0
    do d = 1, b%ndim
      a = (p(d) - r(d) - b%lo(d))*b%inv_cell(d)
      z = (p(d) + r(d) - b%lo(d))*b%inv_cell(d)
      if (z < 0.0_wp .or. a >= real(b%ncg(d), wp)) then
        empty = .true.
        return
      end if
      ! (the whole grid's cells, then the block kept: off = 0, nc = ncg unless a block)
      clo(d) = max(0, int(a), b%off(d)) - b%off(d)
      chi(d) = min(b%ncg(d) - 1, int(z), b%off(d) + b%nc(d) - 1) - b%off(d)
      if (clo(d) > chi(d)) then
        empty = .true.
        return
      end if
    end do
  end subroutine bins_cell_block

  !> Candidate particles whose cell overlaps [p - r, p + r]; list must be large enough.
  pure subroutine bins_candidates(b, p, r, list, n)
    type(bins_t), intent(in) :: b
    real(wp), intent(in) :: p(:), r(:)
    integer, intent(inout) :: list(:)
    integer, intent(out) :: n
    integer :: clo(3), chi(3), k, qa, qb
    logical :: empty
    n = 0
    call bins_cell_block(b, p, r, clo, chi, empty)
    if (empty) return
    do k = 1, bins_block_runs(clo, chi)
      call bins_block_run(b, clo, chi, k, qa, qb)
      list(n + 1:n + qb - qa + 1) = b%idx(qa:qb)
      n = n + qb - qa + 1
    end do
  end subroutine bins_candidates

  !> The runs of the bins' block clo ... chi (bins_cell_block, not empty): one a row of
  !! cells along the first direction, whose points are consecutive in the bins' order.
  pure integer function bins_block_runs(clo, chi) result(n)
    integer, intent(in) :: clo(3), chi(3)
    n = (chi(2) - clo(2) + 1)*(chi(3) - clo(3) + 1)
  end function bins_block_runs

  !> Run k (1 .. bins_block_runs) of the bins' block clo ... chi: the places qa ... qb in
  !! b%idx of its points (none when qb < qa), the rows in bins_candidates' order (the second
  !! direction fastest, then the third): a walk over the block without a candidate list.
  pure subroutine bins_block_run(b, clo, chi, k, qa, qb)
    type(bins_t), intent(in) :: b
    integer, intent(in) :: clo(3), chi(3), k
    integer, intent(out) :: qa, qb
    integer :: nj, c
    nj = chi(2) - clo(2) + 1
    c = 1 + b%nc(1)*(clo(2) + mod(k - 1, nj) + b%nc(2)*(clo(3) + (k - 1)/nj))
    qa = b%start(c + clo(1))
    qb = b%start(c + chi(1) + 1) - 1
  end subroutine bins_block_run

  !> Reference O(N) search: particles with |x_d - p_d| < r_d in every direction.
  pure subroutine bins_brute_force(x, p, r, list, n)
    real(wp), intent(in) :: x(:, :), p(:), r(:)
    integer, intent(inout) :: list(:)
    integer, intent(out) :: n
    integer :: i
    n = 0
    do i = 1, size(x, 2)
      if (all(abs(x(:, i) - p(1:size(x, 1))) < r(1:size(x, 1)))) then
        n = n + 1
        list(n) = i
      end if
    end do
  end subroutine bins_brute_force
end module neighbour_bins_m
