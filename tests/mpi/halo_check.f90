!> The halo exchange over real MPI ranks (issue 12; doc/parallel.md), run by ctest as
!! `mpirun --oversubscribe -np N halo_check` for N = 1..4: every rank builds the solid's
!! tables (RKPM SCNI with stabilization and CST4, plane strain and axisymmetric), takes its
!! part of the recursive coordinate bisection and its halo plan, and
!!   - fills only its owned nodes' coefficients, gets the ghost nodes' by halo_nodes: every
!!     local value must equal the global one to the bit;
!!   - evaluates F and P at its owned points only, gets the ghost points' P and
!!     stabilization stresses by halo_points: equal to the serial ones to the bit;
!!   - gathers the internal force (eq. 72) at its owned nodes: equal to the serial
!!     evaluation on the whole tables to the bit.
!! The serial reference is computed by every rank on the whole tables. Prints the ghost
!! counts and the bytes one exchange moves, and exits 1 (error stop) on any mismatch.
!! Also the bisection over the ranks (rcb_build_ranks): each rank holds a scattered share
!! of a point set (lattices whose rows tie, random points of both signs with zeros of both
!! signs, a set flat along an axis, sets with fewer points than parts), and the tree must
!! be rcb_build's over the whole set, cut for cut, for 1-7 parts on every rank count.
program halo_check
  use mpi_f08
  use kinds_m, only: wp
  use errors_m, only: error_t
  use body_m, only: body_t
  use kernels_m, only: kernel_cubic, window_tensor
  use basis_m, only: basis_bilinear
  use generators_m, only: make_rectangle, set_supports
  use solid_tables_m, only: solid_tables_t
  use rkpm_tl_m, only: tl_build, scheme_scni
  use cst4_m, only: cst4_mesh_t, cst4_rectangle, cst4_tables
  use tl_kinematics_m, only: deformation_gradient, internal_force
  use decomposition_m, only: rcb_tree_t, rcb_build, rcb_build_ranks, rcb_part, local_part_t, &
    local_part_build
  use mpi_comm_m, only: mpi_ranks_t, mpi_ranks_init
  use halo_m, only: halo_plan_t, halo_plan_build, halo_nodes, halo_points
  implicit none
  real(wp), parameter :: stab(2) = [0.1_wp*3.0e11_wp, 0.1_wp*8.0e10_wp]
  integer :: me, nranks, bad, bad_all, icase
  logical :: fem, axisym
  character(len=*), parameter :: names(4) = [character(len=24) :: 'RKPM SCNI axisymmetric', &
    'RKPM SCNI plane strain', 'CST4 plane strain', 'CST4 axisymmetric']
  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, me)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  bad_all = 0
  do icase = 1, 4
    fem = icase >= 3
    axisym = icase == 1 .or. icase == 4
    call check(fem, axisym, trim(names(icase)), bad)
    bad_all = bad_all + bad
  end do
  call check_rcb_ranks(bad)
  bad_all = bad_all + bad
  if (me == 0) then
    if (bad_all == 0) then
      write(*, '(a,i0,a)') 'halo_check: ', nranks, ' rank(s): every value bit for bit'
    else
      write(*, '(a,i0,a,i0,a)') 'halo_check: ', nranks, ' rank(s): ', bad_all, ' mismatches'
    end if
  end if
  call MPI_Finalize()
  if (bad_all /= 0) error stop 1

contains

  subroutine check(fem, axisym, label, nbad)
    logical, intent(in) :: fem, axisym
    character(len=*), intent(in) :: label
    integer, intent(out) :: nbad
    type(body_t) :: b
    type(solid_tables_t) :: t
    type(cst4_mesh_t) :: mesh
    type(error_t), allocatable :: err
    type(rcb_tree_t) :: tree
    type(local_part_t) :: lp
    type(halo_plan_t) :: plan
    real(wp), allocatable :: d(:, :), f(:, :), p(:, :), s(:, :), fint(:, :)
    real(wp), allocatable :: dl(:, :), fl(:, :), pl(:, :), sl(:, :), fil(:, :)
    integer, allocatable :: node_part(:), point_part(:)
    real(wp) :: en
    integer :: i, q, k, mine(4), tot(4)
    if (fem) then
      call cst4_rectangle([0.0_wp, 0.0_wp], [0.004_wp, 0.012_wp], [8, 24], [2.0_wp, 2.0_wp], &
        b, mesh, err)
      if (.not. allocated(err)) call cst4_tables(b, mesh, axisym, 7800.0_wp, t, err)
    else
      call make_rectangle(b, [0.0_wp, 0.0_wp], [0.004_wp, 0.012_wp], [9, 25], err)
      b%kid = kernel_cubic
      b%wshape = window_tensor
      b%bid = basis_bilinear
      call set_supports(b, [2.0_wp, 2.0_wp])
      if (.not. allocated(err)) call tl_build(b, axisym, scheme_scni, 7800.0_wp, t, err)
    end if
    if (allocated(err)) error stop err%message
    ! the serial reference, on every rank
    allocate(d(2, t%np), f(5, t%nq), p(5, t%nq), s(4, t%nq), fint(2, t%np))
    do i = 1, t%np
      d(:, i) = 1.0e-4_wp*[sin(300.0_wp*b%x(2, i)) + 0.1_wp*cos(7.0_wp*i), &
        cos(500.0_wp*b%x(1, i)) - 0.2_wp*sin(3.0_wp*i)]
    end do
    d(1, :) = merge(0.0_wp, d(1, :), t%fix1)
    s = 0.0_wp
    if (fem) then
      call deformation_gradient(t, d, f)
    else
      call deformation_gradient(t, d, f, stab, s, en)
    end if
    do q = 1, t%nq
      p(:, q) = stress_of(f(:, q))
    end do
    if (fem) then
      call internal_force(t, p, fint)
    else
      call internal_force(t, p, fint, s)
    end if
    ! this rank's part and plan
    call rcb_build(b%x, nranks, tree)
    allocate(node_part(t%np), point_part(t%nq))
    do i = 1, t%np
      node_part(i) = rcb_part(tree, b%x(:, i))
    end do
    do q = 1, t%nq
      point_part(q) = rcb_part(tree, t%xq(:, q))
    end do
    call local_part_build(t, node_part, point_part, me + 1, lp)
    call halo_plan_build(MPI_COMM_WORLD, lp, node_part(lp%nglob), point_part(lp%qglob), &
      plan, err)
    if (allocated(err)) error stop err%message
    nbad = 0
    ! nodes: owned values in, ghosts from their owners
    allocate(dl(2, lp%t%np))
    dl = -huge(1.0_wp)
    dl(:, lp%n_owned) = d(:, lp%nglob(lp%n_owned))
    call halo_nodes(plan, dl)
    nbad = nbad + count(dl /= d(:, lp%nglob))
    ! points: F, P, s at owned points, the ghosts' from their owners
    allocate(fl(5, lp%t%nq), pl(5, lp%t%nq), sl(4, lp%t%nq), fil(2, lp%t%np))
    sl = 0.0_wp
    if (fem) then
      call deformation_gradient(lp%t, dl, fl)
    else
      call deformation_gradient(lp%t, dl, fl, stab, sl, en)
    end if
    pl = -huge(1.0_wp)
    do k = 1, size(lp%q_owned)
      pl(:, lp%q_owned(k)) = stress_of(fl(:, lp%q_owned(k)))
    end do
    call halo_points(plan, pl)
    if (.not. fem) call halo_points(plan, sl)
    nbad = nbad + count(pl /= p(:, lp%qglob))
    if (.not. fem) nbad = nbad + count(sl /= s(:, lp%qglob))
    if (fem) then
      call internal_force(lp%t, pl, fil)
    else
      call internal_force(lp%t, pl, fil, sl)
    end if
    nbad = nbad + count(fil(:, lp%n_owned) /= fint(:, lp%nglob(lp%n_owned)))
    mine = [lp%t%np - lp%np_own, lp%t%nq - lp%nq_own, lp%np_own, nbad]
    call MPI_Allreduce(mine, tot, 4, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD)
    nbad = tot(4)
    if (me == 0) write(*, '(a,a,i0,a,i0,a,i0,a,i0,a,i0,a,i0)') label, ': ', nranks, &
      ' rank(s), ', tot(1), ' ghost nodes and ', tot(2), ' ghost points in all (', tot(3), &
      ' nodes), ', 8*(2*tot(1) + 5*tot(2)), ' bytes for one exchange of d and P; mismatches ', &
      nbad
  end subroutine check

  !> The bisection over the ranks against the whole set's (see the header); nbad: the
  !! trees (cases x part counts) that differ anywhere, summed over the ranks.
  subroutine check_rcb_ranks(nbad)
    integer, intent(out) :: nbad
    type(mpi_ranks_t) :: ranks
    type(rcb_tree_t) :: tw, tr
    real(wp), allocatable :: x(:, :)
    integer, allocatable :: mine(:)
    integer :: kase, nparts, n, i, nd, ntrees, sums(2)
    real(wp) :: u
    call mpi_ranks_init(ranks, MPI_COMM_WORLD)
    nbad = 0
    ntrees = 0
    do kase = 1, 5
      select case (kase)
      case (1)   ! a 2D lattice 9 x 25 (rows tie along both axes)
        nd = 2
        n = 225
        allocate(x(nd, n))
        do i = 1, n
          x(:, i) = [0.5_wp*mod(i - 1, 9), 0.5_wp*((i - 1)/9)]
        end do
      case (2)   ! a 3D lattice 6 x 5 x 11 about the origin (zeros, negative rows)
        nd = 3
        n = 330
        allocate(x(nd, n))
        do i = 1, n
          x(:, i) = [real(mod(i - 1, 6) - 3, wp), real(mod((i - 1)/6, 5) - 2, wp), &
            -0.25_wp*real((i - 1)/30, wp)]
        end do
      case (3)   ! random points of both signs, some zeros of either sign
        nd = 3
        n = 401
        allocate(x(nd, n))
        do i = 1, n
          call random_number(u)
          x(1, i) = (u - 0.5_wp)*1.0e-3_wp
          call random_number(u)
          x(2, i) = (u - 0.3_wp)*7.0_wp
          call random_number(u)
          x(3, i) = -u*1.0e5_wp
        end do
        x(1, 1:40:3) = 0.0_wp
        x(1, 2:40:3) = -0.0_wp
        ! (every rank the same points: rank 0's)
        call MPI_Bcast(x, size(x), MPI_DOUBLE_PRECISION, 0, MPI_COMM_WORLD)
      case (4)   ! flat along y and z: every cut across x, ties at the middle
        nd = 3
        n = 64
        allocate(x(nd, n))
        do i = 1, n
          x(:, i) = [real(mod(i*7, 13), wp), 2.0_wp, 2.0_wp]
        end do
      case default   ! fewer points than parts
        nd = 2
        n = 3
        allocate(x(nd, n))
        x = reshape([1.0_wp, 0.0_wp, -1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp], [2, 3])
      end select
      ! a scattered share: point i on rank mod(3 i, nranks)
      mine = pack([(i, i = 1, n)], [(mod(3*i, nranks) == me, i = 1, n)])
      do nparts = 1, 7
        call rcb_build(x, nparts, tw)
        call rcb_build_ranks(x(:, mine), nparts, ranks, tr)
        ntrees = ntrees + 1
        if (tr%nt /= tw%nt .or. any(tr%part /= tw%part) .or. any(tr%axis /= tw%axis) .or. &
          any(tr%lo /= tw%lo) .or. any(tr%hi /= tw%hi) .or. any(tr%cut /= tw%cut)) &
          nbad = nbad + 1
      end do
      deallocate(x)
    end do
    sums = [nbad, ntrees]
    call MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD)
    nbad = sums(1)
    if (me == 0) write(*, '(a,i0,a,i0,a,i0)') 'bisection over the ranks: ', nranks, &
      ' rank(s), ', ntrees, ' trees against the whole set''s; mismatches ', nbad
  end subroutine check_rcb_ranks

  pure function stress_of(f) result(p)
    real(wp), intent(in) :: f(5)
    real(wp) :: p(5)
    p = 1.0e9_wp*[f(1) - 1.0_wp + 0.3_wp*f(2)**2, f(2) - 0.2_wp*f(3), f(3) + f(1)*f(4) - 1.0_wp, &
      f(4) - 1.0_wp + f(2)*f(3), f(5) - 1.0_wp]
  end function stress_of
end program halo_check
