!> How much memory a deck will need, estimated before the big allocations (the bodies, the
!! RKPM and element tables, the query sets) and compared with what the machine has free
!! (MemAvailable of /proc/meminfo), so that a deck too large for the machine is refused
!! with the estimate instead of ending in the runtime's "Error allocating ... bytes" or a
!! crash. The per-particle costs are measured (see the parameters) and rounded up.
module setup_memory_m
  use, intrinsic :: iso_fortran_env, only: output_unit
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use deck_m, only: deck_t, body_spec_t, body_count_var
  use body_m, only: body_t
  use geometry_m, only: polygon_area
  implicit none
  private
  public :: check_memory, memory_available, deck_memory

  !> Per particle of any body: positions, volumes, supports, the det(M) cloud with its bins
  !! (measured: 130 B a particle for a 2000 x 2000 rectangle with --check in mode detect).
  integer(i64), parameter :: body_bytes = 160_i64
  !> Per integration point and candidate neighbour of the RKPM work arrays (gradients,
  !! masses, sub-cell gradients, ids: 84 B, and the positions table: 20 B).
  integer(i64), parameter :: candidate_bytes = 112_i64
  !> Per integration point and covering particle of the compressed RKPM tables (96 B) and
  !! their values in the transpose's order for the force gather (72 B).
  integer(i64), parameter :: neighbour_bytes = 168_i64
  !> Per node of a solid: its state, forces, stresses and their history (rounded up).
  integer(i64), parameter :: solid_bytes = 1024_i64
  !> Per node of a CST4 body (a node and its two triangles' tables, rounded up).
  integer(i64), parameter :: fem_bytes = 2304_i64
  !> 3D RKPM (rkpm_tl3d_m), per candidate neighbour of the set-up's work arrays (the cell's
  !! and the half cells' gradient integrals, mass, id: 60 B compact, 156 B folded across
  !! symmetry planes), counted for one block of block_3d particles (work_bytes: a block's
  !! cell rows and the position table's work, all the build holds beside the tables), and
  !! per covering particle of the tables with their transpose's copies and the position
  !! table (124 B compact, 332 B folded), rounded up. The set-up's peak is then the tables
  !! the time loop keeps. Measured (bench/memory_3d.py, doc/benchmarks.md): 15.4-15.6 kB a
  !! particle at the set-up's peak, 15.1-15.2 kB in the time loop (cubes of 46^3 to 100^3,
  !! support_factor 2, 115-121 entries a point; 30.5 kB at the peak before the blocks); a
  !! folded quarter cylinder (109 entries a point, its target and contact included) 38 kB.
  integer(i64), parameter :: candidate_bytes_3d = 64_i64, candidate_bytes_3d_folded = 160_i64
  integer(i64), parameter :: neighbour_bytes_3d = 128_i64, neighbour_bytes_3d_folded = 336_i64
  !> Particles per block of the 3D table build (rkpm_tl3d_m's block_np).
  integer(i64), parameter :: block_3d = 4096_i64
  !> Per node of a 3D solid: its state (9-component F and P, 6 stresses, ...), rounded up.
  integer(i64), parameter :: solid_bytes_3d = 2048_i64
  !> Per query point of mode detect or of the det(M) fields: position, det, distance, flag.
  integer(i64), parameter :: query_bytes = 48_i64

contains

  !> Refuse the deck when its estimate exceeds the memory available now. Before the bodies
  !! exist, the particle counts come from the deck (a particle file is counted once read:
  !! call again with bodies). Skipped when /proc/meminfo cannot be read.
  subroutine check_memory(deck, err, bodies)
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    type(body_t), intent(in), optional :: bodies(:)
    integer(i64) :: avail, total, worst
    character(len=:), allocatable :: who, what
    avail = memory_available()
    if (avail < 0) return
    call deck_memory(deck, total, worst, who, what, bodies)
    if (present(bodies)) write(output_unit, '(a)') 'memory: about '//bytes_text(total)// &
      ' estimated (largest part: '//what//'), '//bytes_text(avail)//' available'
    if (total <= avail) return
    call set_error(err, "deck '"//deck%path//"', "//who//": the run needs about "// &
      bytes_text(total)//" of memory ("//what//"), more than the "//bytes_text(avail)// &
      " available now (MemAvailable, /proc/meminfo); give fewer particles or query "// &
      "points, or run on a machine with more memory")
  end subroutine check_memory

  !> Estimated bytes of the whole run (total), of its largest part (worst), the group and
  !! variable behind that part (who) and what it is (what).
  subroutine deck_memory(deck, total, worst, who, what, bodies)
    type(deck_t), intent(in) :: deck
    integer(i64), intent(out) :: total, worst
    character(len=:), allocatable, intent(out) :: who, what
    type(body_t), intent(in), optional :: bodies(:)
    integer(i64) :: np, bytes, nq
    integer :: k, nd
    nd = deck%run%ndim
    total = 0
    worst = -1
    who = 'group &run'
    what = ''
    do k = 1, deck%nbodies
      associate (s => deck%bodies(k))
        if (present(bodies)) then
          np = bodies(k)%np
        else
          np = particle_count(s, nd)
        end if
        bytes = np*particle_bytes(deck, s) + work_bytes(deck, s, np)
        total = total + bytes
        if (bytes > worst) then
          worst = bytes
          who = "group &body (body "//itoa(k)//", '"//trim(s%name)//"'), variable "// &
            body_count_var(s%shape)//" = "//count_value(s, nd)
          what = "body '"//trim(s%name)//"': "//count_text(np)//" particles, about "// &
            bytes_text(bytes)
        end if
      end associate
    end do
    if (deck%run%mode == 'detect' .and. deck%detection%present) then
      nq = max(deck%detection%line_n, 0) + deck%detection%npoints
      if (any(deck%detection%grid_n(1:nd) > 0)) nq = nq + &
        product(int(max(deck%detection%grid_n(1:nd), 1), i64))
      bytes = nq*query_bytes
      total = total + bytes
      if (bytes > worst) then
        worst = bytes
        who = 'group &detection, variable grid_n/line_n'
        what = count_text(nq)//' query points, about '//bytes_text(bytes)
      end if
    end if
    if (deck%run%mode == 'dynamic' .and. deck%output%det_fields) then
      ! the grid of one pair's master and slave at a time
      nq = 2*product(int(max(deck%output%det_grid_n, 1), i64))
      bytes = nq*query_bytes
      total = total + bytes
      if (bytes > worst) then
        worst = bytes
        who = 'group &output, variable det_grid_n'
        what = count_text(nq)//' det(M) field points, about '//bytes_text(bytes)
      end if
    end if
  end subroutine deck_memory

  !> Particles (nodes) a body spec will make; 0 for a particle file not read yet.
  function particle_count(s, nd) result(np)
    type(body_spec_t), intent(in) :: s
    integer, intent(in) :: nd
    integer(i64) :: np
    real(wp) :: perimeter, a
    integer :: k, nv
    np = 0
    select case (s%shape)
    case ('segment')
      np = s%n(1)
    case ('rectangle')
      np = int(s%n(1), i64)*s%n(2)
      ! the box centres of a CST4 mesh are nodes too
      if (s%discretization == 'fem') np = np + int(s%n(1) - 1, i64)*(s%n(2) - 1)
    case ('annulus_sector')
      np = int(s%n(1), i64)*s%n(2)
    case ('polygon')
      nv = s%nvert
      a = abs(polygon_area(s%vertices(:, 1:nv), nv))
      perimeter = 0.0_wp
      do k = 1, nv
        perimeter = perimeter + norm2(s%vertices(:, merge(1, k + 1, k == nv)) - &
          s%vertices(:, k))
      end do
      np = int(min(a/product(s%spacing(1:2)) + perimeter/minval(s%spacing(1:2)) + 1.0_wp, &
        real(huge(1_i64), wp)/1.0e4_wp), i64)
    end select
    if (nd < 1) np = 0
  end function particle_count

  !> Bytes per particle of a body in this deck.
  function particle_bytes(deck, s) result(bytes)
    type(deck_t), intent(in) :: deck
    type(body_spec_t), intent(in) :: s
    integer(i64) :: bytes
    real(wp) :: sf(2)
    integer(i64) :: maxk, ncover
    bytes = body_bytes
    if (deck%run%mode /= 'dynamic' .or. s%role /= 'deformable') return
    if (s%discretization == 'fem') then
      bytes = bytes + fem_bytes
      return
    end if
    if (deck%run%ndim == 3) then
      ! particles covering the cell's faces (2 support_factor + 1 per direction: 125 inside
      ! at support_factor 2, 101-121 a point with the surface); the work arrays: work_bytes
      ncover = int(product(2.0_wp*s%support_factor(1:3) + 1.0_wp), i64)
      if (folded_3d(s)) then
        bytes = bytes + neighbour_bytes_3d_folded*ncover
      else
        bytes = bytes + neighbour_bytes_3d*ncover
      end if
      bytes = bytes + solid_bytes_3d
      return
    end if
    ! lattice counts: candidates in a cell grown by the largest support, particles covering
    ! a point (2 support_factor per direction)
    sf = s%support_factor(1:2)
    maxk = int((2.0_wp*maxval(sf) + 2.0_wp)**2, i64)
    ncover = max(1_i64, int(4.0_wp*sf(1)*sf(2), i64))
    bytes = bytes + candidate_bytes*maxk + neighbour_bytes*ncover + solid_bytes
  end function particle_bytes

  !> Bytes of a body's set-up work arrays that do not grow with its np particles: the 3D
  !! RKPM build's, one block of particles at a time (rkpm_tl3d_m).
  function work_bytes(deck, s, np) result(bytes)
    type(deck_t), intent(in) :: deck
    type(body_spec_t), intent(in) :: s
    integer(i64), intent(in) :: np
    integer(i64) :: bytes, maxk
    bytes = 0
    if (deck%run%mode /= 'dynamic' .or. s%role /= 'deformable' .or. deck%run%ndim /= 3 .or. &
      s%discretization == 'fem') return
    ! candidates in a cell grown by the largest support
    maxk = int((2.0_wp*maxval(s%support_factor(1:3)) + 2.0_wp)**3, i64)
    if (folded_3d(s)) then
      bytes = min(np, block_3d)*candidate_bytes_3d_folded*maxk
    else
      bytes = min(np, block_3d)*candidate_bytes_3d*maxk
    end if
  end function work_bytes

  !> A 3D body whose shape functions are folded across symmetry planes (a cylinder's sector).
  pure logical function folded_3d(s)
    type(body_spec_t), intent(in) :: s
    folded_3d = s%shape == 'cylinder' .and. s%theta_end < 360.0_wp
  end function folded_3d

  !> The deck's value of the variable that sets a body's particle count, as text.
  function count_value(s, nd) result(t)
    type(body_spec_t), intent(in) :: s
    integer, intent(in) :: nd
    character(len=:), allocatable :: t
    integer :: d
    select case (s%shape)
    case ('polygon')
      t = rtoa(s%spacing(1))//', '//rtoa(s%spacing(2))
    case ('file', 'geo')
      t = "'"//trim(s%file)//"'"
    case default
      t = itoa(s%n(1))
      do d = 2, max(nd, 1)
        t = t//', '//itoa(s%n(d))
      end do
    end select
  end function count_value

  !> Bytes free for a new process: MemAvailable of /proc/meminfo; -1 when unreadable.
  function memory_available() result(bytes)
    integer(i64) :: bytes
    integer :: u, ios
    character(len=256) :: line
    integer(i64) :: kb
    bytes = -1
    open(newunit=u, file='/proc/meminfo', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, 'MemAvailable:') == 1) then
        read(line(len('MemAvailable:') + 1:), *, iostat=ios) kb
        if (ios == 0 .and. kb >= 0) bytes = kb*1024_i64
        exit
      end if
    end do
    close(u)
  end function memory_available

  !> "12.3 GB", "456 MB", ...
  function bytes_text(b) result(t)
    integer(i64), intent(in) :: b
    character(len=:), allocatable :: t
    character(len=32) :: buf
    real(wp) :: x
    character(len=2), parameter :: units(5) = ['B ', 'kB', 'MB', 'GB', 'TB']
    integer :: k
    x = real(b, wp)
    k = 1
    do while (x >= 1000.0_wp .and. k < size(units))
      x = x/1000.0_wp
      k = k + 1
    end do
    write(buf, '(f0.1)') x
    t = trim(adjustl(buf))//' '//trim(units(k))
  end function bytes_text

  !> A count as text, in powers of ten when large ("1.00e10").
  function count_text(n) result(t)
    integer(i64), intent(in) :: n
    character(len=:), allocatable :: t
    character(len=32) :: buf
    if (n < 10000000_i64) then
      write(buf, '(i0)') n
    else
      write(buf, '(es9.2)') real(n, wp)
    end if
    t = trim(adjustl(buf))
  end function count_text
end module setup_memory_m
