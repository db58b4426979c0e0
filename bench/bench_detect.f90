!> Contact-detection benchmark (det(M) of eqs. (5)-(6), the criterion of eqs. (25)-(28), the
!! buffer zone of Section 3, Fig. 11; issue 2). Not a test: it times and
!! prints, it never fails on a time.
!!
!! Part A, throughput: det(M) of the Taylor bar's half-section (31 x 361 particles,
!! dx = dy = 1/6 mm, rho = 2.24 dx, cubic tensor window, bilinear basis) at 10^6 random
!! query points, (a) in the body's bounding box and (b) in a box 1.5 times larger, on 1 and 2
!! threads, best of 5 after a warm-up. Variants: the specialised path (det_at_points ->
!! cloud_det -> det_2d_bilinear_tensor), the generic path (cloud_moment + chol_small), and
!! the generic assembly with LAPACK dpotrf, plus the specialised path on cell-sorted queries.
!!
!! Part B, accuracy: det(M) > eps_cr (5e-10) against the exact geometry (rectangle, L-shape,
!! annulus sector) at three resolutions each, on a grid of spacing dx/8 covering the body
!! plus 2 rho: points inside the body classified outside (must be 0), and the widest
!! outside point classified inside against rho_buffer = sqrt(rho_x^2 + rho_y^2) (eq. 50).
!!
!! Part C, 3D throughput (issue 23): det(M) of a box of particles (the
!! Taylor bar's 10 x 10 x 60 mm bounding box, 16 x 16 x 91 at 2/3 mm), linear
!! basis, cubic tensor window, rho = 2.24 dx, at 10^6 random points in its bounding box, on
!! 1 and 2 threads: the library path (det_at_points -> cloud_det -> det_3d_linear_tensor)
!! against the plain compiled loop of the same arithmetic (det_variants_m's det_plain_3d)
!! in the same run, and the generic path (cloud_moment + chol_small).
!!
!! Output: 'RESULT key=value ...' lines for scripts, and human tables.
program bench_detect
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, int64
  use omp_lib, only: omp_get_wtime, omp_set_num_threads, omp_get_max_threads
  use kinds_m, only: wp, pi
  use errors_m, only: error_t
  use body_m, only: body_t
  use generators_m, only: make_rectangle, make_polygon, make_annulus, set_supports, &
    extrude_body
  use detection_m, only: body_cloud
  use kernels_m, only: kernel_cubic, window_tensor
  use basis_m, only: basis_bilinear, basis_linear_3d, mmax
  use rk_cloud_m, only: rk_cloud_t, cloud_moment
  use moment_matrix_m, only: chol_small, chol_det, singular_pivot
  use detection_m, only: det_at_points, body_plateau, classify, buffer_stats, buffer_stats_t
  use sorting_m, only: sort_index
  use det_variants_m, only: soa_cloud_t, soa_build, fine_cloud, det_copy, det_inline, &
    det_branchless, det_soa, det_plain_3d
  implicit none

  interface
    !> LAPACK Cholesky factorization (explicit interface, STYLE rule 2 of tblite).
    pure subroutine dpotrf(uplo, n, a, lda, info)
      import :: wp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, lda
      real(wp), intent(inout) :: a(lda, *)
      integer, intent(out) :: info
    end subroutine dpotrf
  end interface

  !> Kernels: the library's det_at_points (specialised path), the generic assembly with
  !! chol_small or dpotrf, and the experiments of det_variants_m.
  integer, parameter :: k_lib = 1, k_generic = 2, k_lapack = 3, k_copy = 4, k_inline = 5, &
    k_branchless = 6, k_soa = 7, k_plain3d = 8
  !> Variants timed: a kernel, on the cloud as cloud_init built it (vcell = 0) or repacked
  !! on bins of cells rmax/vcell, with the queries in random or in cell order (sorted).
  !! Names starting 'x_' are experiments, not library code.
  integer, parameter :: nvar = 13
  integer, parameter :: v_special = 1, v_generic = 2, v_lapack = 3
  character(len=*), parameter :: vname(nvar) = [character(len=13) :: &
    'specialised', 'generic', 'lapack', 'sorted', 'x_copy', 'x_inline', 'x_branchless', &
    'x_soa', 'x_lib_c2', 'x_inline_c2', 'x_inline_c3', 'x_soa_c2', 'x_soa_c2_sort']
  integer, parameter :: vkern(nvar) = [k_lib, k_generic, k_lapack, k_lib, k_copy, &
    k_inline, k_branchless, k_soa, k_lib, k_inline, k_inline, k_soa, k_soa]
  !> 0: the library's own bins; k > 0: bins of cell size rmax/k
  integer, parameter :: vcell(nvar) = [0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 3, 2, 2]
  logical, parameter :: vsort(nvar) = [.false., .false., .false., .true., .false., &
    .false., .false., .false., .false., .false., .false., .false., .true.]
  integer, parameter :: nquery = 1000000
  integer, parameter :: nrep = 5
  real(wp), parameter :: target_qps = 5.0e6_wp   !< issue 2: one core, bounding box
  real(wp), parameter :: mm_ = 1.0e-3_wp          !< one millimetre (m)
  real(wp), parameter :: support_factor = 2.24_wp
  real(wp), parameter :: eps_cr = 5.0e-10_wp
  real(wp), parameter :: agree_tol = 1.0e-10_wp   !< relative det difference allowed
  real(wp), parameter :: det_floor = 1.0e-20_wp   !< compare det only above this
  integer :: nround
  logical :: do_throughput, do_accuracy, do_3d

  write(output_unit, '(a)') '# bench_detect: meshfree contact detection (Li et al. 2001)'
  write(output_unit, '(a,i0)') '# OpenMP max threads: ', omp_get_max_threads()
  call read_args(nround, do_throughput, do_accuracy, do_3d)
  if (do_throughput) call throughput(nround)
  if (do_accuracy) call accuracy()
  if (do_3d) call throughput_3d(nround)

contains

  !> Part A.
  subroutine throughput(nround)
    integer, intent(in) :: nround
    type(body_t) :: b
    type(rk_cloud_t) :: c
    !> cf(0): c as cloud_init built it; cf(k): c repacked on bins of cells rmax/k
    type(rk_cloud_t), target :: cf(0:3)
    type(soa_cloud_t), target :: sf(0:3)
    type(rk_cloud_t), pointer :: cv
    type(soa_cloud_t), pointer :: sv
    type(error_t), allocatable :: err
    real(wp), allocatable :: p(:, :), ps(:, :), d_ref(:), d(:)
    real(wp) :: lo(2), hi(2), ctr(2), half(2), t, qps(nvar, 2, 2), cand, hits
    integer :: iset, v, nt, round, k
    character(len=*), parameter :: setname(2) = [character(len=6) :: 'bbox', 'bbox15']
    lo = [0.0_wp, 0.0_wp]
    hi = [5.0_wp*mm_, 60.0_wp*mm_]
    call make_rectangle(b, lo, hi, [31, 361], err)
    call check(err)
    call set_supports(b, [support_factor, support_factor])
    b%kid = kernel_cubic
    b%wshape = window_tensor
    b%bid = basis_bilinear
    call body_cloud(b, c, err)
    call check(err)
    cf(0) = c
    call soa_build(cf(0), sf(0))
    do k = 1, 3
      call fine_cloud(c, k, cf(k), err)
      call check(err)
      call soa_build(cf(k), sf(k))
    end do
    write(output_unit, '(/,a)') '## A. Throughput: Taylor bar half-section, det(M) queries'
    write(output_unit, '(a,i0,a,es10.3,a,es10.3,a,i0,a,i0,a,f0.2,a,i0,a)') '# particles ', &
      b%np, ', dx = ', b%spacing(1), ' m, rho = ', b%rho(1, 1), ' m, library bins ', &
      c%bins%nc(1), ' x ', c%bins%nc(2), ' (cell = rmax/', c%rmax(1)/c%bins%cell(1), '); ', &
      nquery, ' queries, best of 5 after a warm-up'
    write(output_unit, '(a,es12.5)') '# interior plateau of det(M): ', body_plateau(b, c)
    allocate(p(2, nquery), ps(2, nquery), d_ref(nquery), d(nquery))
    ctr = 0.5_wp*(lo + hi)
    do iset = 1, 2
      half = 0.5_wp*(hi - lo)
      if (iset == 2) half = 1.5_wp*half
      call random_points(ctr - half, ctr + half, 12345 + iset, p)
      call sort_by_cell(c, p, ps)
      call neighbour_counts(c, p, cand, hits)
      write(output_unit, '(/,a,a,a,2es11.3,a,2es11.3,a,f6.1,a,f6.1)') '# set ', &
        trim(setname(iset)), ': box ', ctr - half, ' ..', ctr + half, &
        '; candidates/query ', cand, ', in support ', hits
      write(output_unit, '(a,a,a,f0.2,a,f0.2)') 'RESULT bench=neighbours set=', &
        trim(setname(iset)), ' cells=library candidates_per_query=', cand, &
        ' hits_per_query=', hits
      do k = 1, 3
        call neighbour_counts(cf(k), p, cand, hits)
        write(output_unit, '(a,a,a,i0,a,f0.2,a,f0.2)') 'RESULT bench=neighbours set=', &
          trim(setname(iset)), ' cells=rmax/', k, ' candidates_per_query=', cand, &
          ' hits_per_query=', hits
      end do
      ! rounds of (threads, variants): a transient load on the shared machine spoils one
      ! round of a variant, not all of them; the best over rounds is kept
      qps(:, :, iset) = 0.0_wp
      do round = 1, nround
        do nt = 1, 2
          do v = 1, nvar
            cv => cf(vcell(v))
            sv => sf(vcell(v))
            if (vsort(v)) then
              t = best_time(vkern(v), cv, sv, ps, d, nt)
            else
              t = best_time(vkern(v), cv, sv, p, d, nt)
            end if
            qps(v, nt, iset) = max(qps(v, nt, iset), real(nquery, wp)/t)
            if (round > 1 .or. nt /= 1 .or. vsort(v)) cycle
            if (v == v_special) then
              d_ref = d
            else
              call agreement(setname(iset), v, d_ref, d)
            end if
          end do
        end do
      end do
      do nt = 1, 2
        do v = 1, nvar
          write(output_unit, '(a,a,a,a,a,i0,a,es12.5,a,f0.2)') &
            'RESULT bench=throughput set=', trim(setname(iset)), ' variant=', &
            trim(vname(v)), ' threads=', nt, ' qps=', qps(v, nt, iset), &
            ' ns_per_query=', 1.0e9_wp/qps(v, nt, iset)
        end do
      end do
    end do
    call throughput_table(qps, setname)
    call factor_only(c, p)
    call query_overhead(c, p, d)
  end subroutine throughput

  !> Fixed cost of one query (det_at_points -> cloud_det -> bins_cell_block and return) on
  !! points whose support box misses the bins entirely. One thread.
  subroutine query_overhead(c, p, d)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(inout) :: p(:, :)
    real(wp), intent(out) :: d(:)
    integer :: r
    real(wp) :: t0, tbest
    call random_points([1.0_wp, 1.0_wp], [2.0_wp, 2.0_wp], 777, p)
    call omp_set_num_threads(1)
    tbest = huge(1.0_wp)
    do r = 0, nrep
      t0 = omp_get_wtime()
      call det_at_points(c, p, d)
      if (r > 0) tbest = min(tbest, omp_get_wtime() - t0)
    end do
    tbest = tbest/real(size(p, 2), wp)*1.0e9_wp
    write(output_unit, '(a,f0.1,a)') '# fixed cost of a query with no candidate cell: ', &
      tbest, ' ns (1 thread)'
    write(output_unit, '(a,f0.2)') 'RESULT bench=query_overhead empty_block_ns=', tbest
  end subroutine query_overhead

  subroutine throughput_table(qps, setname)
    real(wp), intent(in) :: qps(nvar, 2, 2)
    character(len=*), intent(in) :: setname(2)
    integer :: iset, v
    write(output_unit, '(/,a)') '| query set | variant       | 1 thread (M/s) | ns/query | '// &
      '2 threads (M/s) | speed-up 2T/1T |'
    write(output_unit, '(a)') '|---|---|---|---|---|---|'
    do iset = 1, 2
      do v = 1, nvar
        write(output_unit, '(a,a8,a,a13,a,f14.2,a,f8.1,a,f15.2,a,f14.2,a)') '| ', &
          setname(iset), '  | ', vname(v), ' | ', qps(v, 1, iset)*1.0e-6_wp, ' | ', &
          1.0e9_wp/qps(v, 1, iset), ' | ', qps(v, 2, iset)*1.0e-6_wp, ' | ', &
          qps(v, 2, iset)/qps(v, 1, iset), ' |'
      end do
    end do
    write(output_unit, '(a)') '# specialised: det_at_points (library); generic: '// &
      'cloud_moment + chol_small; lapack: cloud_moment + dpotrf; sorted: library on '// &
      'cell-ordered queries'
    write(output_unit, '(a)') '# x_*: experiments in bench/det_variants_m.f90 (not library '// &
      'code) on bins of cells rmax; _c2/_c3: cells rmax/2, rmax/3; _sort: cell-ordered queries'
    do iset = 1, 2
      write(output_unit, '(a,a,a,f0.2,a,f0.2,a,f4.2)') 'RESULT bench=summary set=', &
        trim(setname(iset)), ' specialised_1t_mqps=', qps(v_special, 1, iset)*1.0e-6_wp, &
        ' specialised_2t_mqps=', qps(v_special, 2, iset)*1.0e-6_wp, ' speedup_2t=', &
        qps(v_special, 2, iset)/qps(v_special, 1, iset)
      write(output_unit, '(a,a,a,f0.2,a,f0.2,a,f0.2)') 'RESULT bench=paths set=', &
        trim(setname(iset)), ' specialised_ns=', 1.0e9_wp/qps(v_special, 1, iset), &
        ' generic_ns=', 1.0e9_wp/qps(v_generic, 1, iset), ' lapack_ns=', &
        1.0e9_wp/qps(v_lapack, 1, iset)
    end do
    ! issue 2: >= 5e6 queries/s on one core in the bounding box, >= 1.7x that on two
    write(output_unit, '(a,f0.2,a,a,a,f4.2,a,a,a,f0.2,a,a)') 'RESULT bench=targets '// &
      'one_core_mqps=', qps(v_special, 1, 1)*1.0e-6_wp, ' one_core_ge_5=', &
      trim(merge('yes', 'no ', qps(v_special, 1, 1) >= target_qps)), ' speedup_2t=', &
      qps(v_special, 2, 1)/qps(v_special, 1, 1), ' speedup_ge_1.7=', &
      trim(merge('yes', 'no ', qps(v_special, 2, 1) >= 1.7_wp*qps(v_special, 1, 1))), &
      ' two_core_mqps=', qps(v_special, 2, 1)*1.0e-6_wp, ' two_core_ge_8.5=', &
      trim(merge('yes', 'no ', qps(v_special, 2, 1) >= 1.7_wp*target_qps))
  end subroutine throughput_table

  !> Best wall time of nrep runs of kernel k after one warm-up, on nt threads.
  real(wp) function best_time(k, c, s, p, d, nt) result(tbest)
    integer, intent(in) :: k, nt
    type(rk_cloud_t), intent(in) :: c
    type(soa_cloud_t), intent(in) :: s
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: d(:)
    integer :: r
    real(wp) :: t0
    call omp_set_num_threads(nt)
    tbest = huge(1.0_wp)
    do r = 0, nrep
      t0 = omp_get_wtime()
      select case (k)
      case (k_lib)
        call det_at_points(c, p, d)
      case (k_generic)
        call det_generic(c, p, d)
      case (k_lapack)
        call det_lapack(c, p, d)
      case default
        call det_experiment(k, c, s, p, d)
      end select
      if (r > 0) tbest = min(tbest, omp_get_wtime() - t0)
    end do
  end function best_time

  !> The generic path: full moment matrix, then the hand-coded chol_small.
  subroutine det_generic(c, p, det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: det(:)
    real(wp) :: mm(mmax, mmax)
    integer :: i, ncover
    logical :: ok
    !$omp parallel do default(none) shared(c, p, det) private(mm, ncover, ok) &
    !$omp schedule(static, 256)
    do i = 1, size(p, 2)
      call cloud_moment(c, p(:, i), mm, ncover)
      det(i) = 0.0_wp
      if (ncover == 0) cycle
      call chol_small(c%m, mm, ok, singular_pivot)
      if (ok) det(i) = chol_det(c%m, mm)
    end do
    !$omp end parallel do
  end subroutine det_generic

  !> The same assembly, factorized by LAPACK dpotrf (upper triangle).
  subroutine det_lapack(c, p, det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: det(:)
    real(wp) :: mm(mmax, mmax), diag(mmax)
    integer :: i, k, ncover, info
    !$omp parallel do default(none) shared(c, p, det) private(mm, diag, ncover, info, k) &
    !$omp schedule(static, 256)
    do i = 1, size(p, 2)
      call cloud_moment(c, p(:, i), mm, ncover)
      det(i) = 0.0_wp
      if (ncover == 0) cycle
      diag(1:c%m) = [(mm(k, k), k = 1, c%m)]
      call dpotrf('U', c%m, mm, mmax, info)
      ! info > 0: a non-positive leading minor, i.e. det(M) <= 0 (outside); info < 0 is a
      ! bad argument, which cannot happen with these constants. Then the library's rule:
      ! a pivot below singular_pivot x M_jj counts as singular.
      if (info /= 0) cycle
      if (any([(mm(k, k)**2 <= singular_pivot*diag(k), k = 1, c%m)])) cycle
      det(i) = 1.0_wp
      do k = 1, c%m
        det(i) = det(i)*mm(k, k)**2
      end do
    end do
    !$omp end parallel do
  end subroutine det_lapack

  !> The det_variants_m kernels, with det_at_points' loop and schedule.
  subroutine det_experiment(k, c, s, p, det)
    integer, intent(in) :: k
    type(rk_cloud_t), intent(in) :: c
    type(soa_cloud_t), intent(in) :: s
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: det(:)
    integer :: i
    select case (k)
    case (k_copy)
      !$omp parallel do default(none) shared(c, p, det) schedule(static, 256)
      do i = 1, size(p, 2)
        det(i) = det_copy(c, p(:, i))
      end do
      !$omp end parallel do
    case (k_inline)
      !$omp parallel do default(none) shared(c, p, det) schedule(static, 256)
      do i = 1, size(p, 2)
        det(i) = det_inline(c, p(:, i))
      end do
      !$omp end parallel do
    case (k_branchless)
      !$omp parallel do default(none) shared(c, p, det) schedule(static, 256)
      do i = 1, size(p, 2)
        det(i) = det_branchless(c, p(:, i))
      end do
      !$omp end parallel do
    case (k_soa)
      !$omp parallel do default(none) shared(c, s, p, det) schedule(static, 256)
      do i = 1, size(p, 2)
        det(i) = det_soa(c, s, p(:, i))
      end do
      !$omp end parallel do
    case (k_plain3d)
      !$omp parallel do default(none) shared(c, p, det) schedule(static, 256)
      do i = 1, size(p, 2)
        det(i) = det_plain_3d(c, p(:, i))
      end do
      !$omp end parallel do
    end select
  end subroutine det_experiment

  !> Part C: 3D throughput, the library path against the plain loop in the same run.
  subroutine throughput_3d(nround)
    integer, intent(in) :: nround
    type(body_t) :: b2, b
    type(rk_cloud_t) :: c
    type(soa_cloud_t) :: s
    type(error_t), allocatable :: err
    real(wp), allocatable :: p(:, :), d_lib(:), d(:)
    real(wp) :: qps(3, 2), t, dmax, dref
    integer :: round, nt, v, i
    integer, parameter :: kern(3) = [k_lib, k_plain3d, k_generic]
    character(len=*), parameter :: name3(3) = [character(len=11) :: 'library', 'plain_loop', &
      'generic']
    ! the Taylor bar's bounding box in 3D, 10 x 10 x 60 mm at 2/3 mm: 16 x 16 x 91
    call make_rectangle(b2, [0.0_wp, 0.0_wp], [10.0_wp*mm_, 10.0_wp*mm_], [16, 16], err)
    call check(err)
    call extrude_body(b2, 0.0_wp, 60.0_wp*mm_, 91, b, err)
    call check(err)
    call set_supports(b, [support_factor, support_factor, support_factor])
    b%kid = kernel_cubic
    b%wshape = window_tensor
    b%bid = basis_linear_3d
    call body_cloud(b, c, err)
    call check(err)
    write(output_unit, '(/,a)') '## C. Throughput in 3D: a 10 x 10 x 60 mm box, linear basis'
    write(output_unit, '(a,i0,a,es10.3,a,i0,a)') '# particles ', b%np, ', dx = ', &
      b%spacing(1), ' m, rho = 2.24 dx; ', nquery, ' queries in the bounding box, best of 5'
    allocate(p(3, nquery), d_lib(nquery), d(nquery))
    call random_points3(minval(b%x, dim=2), maxval(b%x, dim=2), 4242, p)
    qps = 0.0_wp
    do round = 1, nround
      do nt = 1, 2
        do v = 1, 3
          t = best_time(kern(v), c, s, p, d, nt)
          qps(v, nt) = max(qps(v, nt), real(nquery, wp)/t)
          if (round == 1 .and. nt == 1 .and. v == 1) d_lib = d
          if (round == 1 .and. nt == 1 .and. v > 1) then
            dmax = 0.0_wp
            dref = maxval(d_lib)
            do i = 1, nquery
              dmax = max(dmax, abs(d(i) - d_lib(i)))
            end do
            write(output_unit, '(a,a,a,es10.3)') '# ', trim(name3(v)), &
              ': largest |det - library det| / largest det = ', dmax/dref
          end if
        end do
      end do
    end do
    write(output_unit, '(a)') '| path | 1 thread (M/s) | 2 threads (M/s) | speed-up |'
    write(output_unit, '(a)') '|---|---|---|---|'
    do v = 1, 3
      write(output_unit, '(a,a,a,f6.3,a,f6.3,a,f5.2,a)') '| ', trim(name3(v)), ' | ', &
        qps(v, 1)*1.0e-6_wp, ' | ', qps(v, 2)*1.0e-6_wp, ' | ', qps(v, 2)/qps(v, 1), ' |'
      do nt = 1, 2
        write(output_unit, '(a,a,a,i0,a,es12.5)') 'RESULT bench=throughput3d variant=', &
          trim(name3(v)), ' threads=', nt, ' qps=', qps(v, nt)
      end do
    end do
    do nt = 1, 2
      write(output_unit, '(a,i0,a,f5.3)') 'RESULT bench=throughput3d ratio=library/plain '// &
        'threads=', nt, ' value=', qps(1, nt)/qps(2, nt)
    end do
  end subroutine throughput_3d

  !> n random points in the box [lo, hi] (3D), reproducible from seed.
  subroutine random_points3(lo, hi, seed, p)
    real(wp), intent(in) :: lo(3), hi(3)
    integer, intent(in) :: seed
    real(wp), intent(out) :: p(:, :)
    integer :: n
    integer, allocatable :: sd(:)
    call random_seed(size=n)
    allocate(sd(n))
    sd = seed
    call random_seed(put=sd)
    call random_number(p)
    do n = 1, size(p, 2)
      p(:, n) = lo + (hi - lo)*p(:, n)
    end do
  end subroutine random_points3

  !> Print how far variant v's det departs from the specialised path's. Relative differences
  !! are reported where det > 1e-20, 1e-15 and eps_cr (where the classification is decided),
  !! with the number of points classified differently at eps_cr. Near det = 0 the last
  !! Cholesky pivot is a difference of nearly equal numbers, so the relative difference
  !! between two summation orders grows like round-off x plateau / det there.
  subroutine agreement(setname, v, dref, d)
    character(len=*), intent(in) :: setname
    integer, intent(in) :: v
    real(wp), intent(in) :: dref(:), d(:)
    real(wp) :: rel_floor, rel_15, rel_eps, det_at_worst, r
    integer :: i, nclass
    rel_floor = 0.0_wp
    rel_15 = 0.0_wp
    rel_eps = 0.0_wp
    det_at_worst = 0.0_wp
    nclass = 0
    do i = 1, size(d)
      if ((dref(i) > eps_cr) .neqv. (d(i) > eps_cr)) nclass = nclass + 1
      if (dref(i) <= det_floor) cycle
      r = abs(d(i) - dref(i))/dref(i)
      if (r > rel_floor) then
        rel_floor = r
        det_at_worst = dref(i)
      end if
      if (dref(i) > 1.0e-15_wp) rel_15 = max(rel_15, r)
      if (dref(i) > eps_cr) rel_eps = max(rel_eps, r)
    end do
    write(output_unit, '(a,a,a,a,a,es9.2,a,es9.2,a,es9.2,a,es9.2,a,i0,a,a,a,a)') &
      'RESULT bench=agreement set=', trim(setname), ' variant=', trim(vname(v)), &
      ' max_rel_diff_det_gt_1e-20=', rel_floor, ' at_det=', det_at_worst, &
      ' max_rel_diff_det_gt_1e-15=', rel_15, &
      ' max_rel_diff_det_gt_eps=', rel_eps, ' class_mismatch=', nclass, &
      ' ok_1e-20=', trim(merge('yes', 'no ', rel_floor < agree_tol)), &
      ' ok_eps=', trim(merge('yes', 'no ', rel_eps < agree_tol .and. nclass == 0))
  end subroutine agreement

  !> Cost of the 4x4 factorization alone, on moment matrices assembled once: chol_small
  !! (generic loops, assumed shape), dpotrf, and the hand-coded fully unrolled form of the
  !! specialised path. One thread; points inside the body.
  subroutine factor_only(c, p)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:, :)
    integer, parameter :: nmat = 100000
    real(wp), allocatable :: ms(:, :, :)
    real(wp) :: mm(mmax, mmax), a(4, 4), t0, tbest(3), sink(3), dt
    integer :: i, r, k, ncover, info, meth
    logical :: ok
    allocate(ms(4, 4, nmat))
    do i = 1, nmat
      call cloud_moment(c, p(:, i), mm, ncover)
      ms(:, :, i) = mm(1:4, 1:4)
    end do
    tbest = huge(1.0_wp)
    sink = 0.0_wp
    do meth = 1, 3
      do r = 0, nrep
        t0 = omp_get_wtime()
        do i = 1, nmat
          a = ms(:, :, i)
          select case (meth)
          case (1)
            call chol_small(4, a, ok, singular_pivot)
            if (ok) sink(1) = sink(1) + chol_det(4, a)
          case (2)
            call dpotrf('U', 4, a, 4, info)
            if (info /= 0) cycle
            if (any([(a(k, k)**2 <= singular_pivot*ms(k, k, i), k = 1, 4)])) cycle
            sink(2) = sink(2) + product([(a(k, k), k = 1, 4)])**2
          case (3)
            sink(3) = sink(3) + chol4_inline(a)
          end select
        end do
        dt = omp_get_wtime() - t0
        if (r > 0) tbest(meth) = min(tbest(meth), dt)
      end do
    end do
    tbest = tbest/real(nmat, wp)*1.0e9_wp
    write(output_unit, '(/,a,i0,a)') '# 4x4 factorization alone (', nmat, &
      ' stored moment matrices, 1 thread, copy of the matrix included):'
    write(output_unit, '(a,f0.1,a,f0.1,a,f0.1,a)') '#   chol_small + chol_det ', tbest(1), &
      ' ns, dpotrf ', tbest(2), ' ns, unrolled (specialised path) ', tbest(3), ' ns'
    write(output_unit, '(a,f0.2,a,f0.2,a,f0.2,a,es9.2)') 'RESULT bench=factor_only '// &
      'chol_small_ns=', tbest(1), ' dpotrf_ns=', tbest(2), ' unrolled_ns=', tbest(3), &
      ' checksum_rel_diff=', maxval(abs(sink - sink(1)))/sink(1)
  end subroutine factor_only

  !> The specialised path's unrolled 4x4 Cholesky on a full matrix (upper triangle used).
  pure real(wp) function chol4_inline(a) result(det)
    real(wp), intent(in) :: a(4, 4)
    real(wp) :: l11, l21, l31, l41, l22, l32, l42, l33, l43, l44, s
    det = 0.0_wp
    if (a(1, 1) <= 0.0_wp) return
    l11 = sqrt(a(1, 1))
    l21 = a(1, 2)/l11
    l31 = a(1, 3)/l11
    l41 = a(1, 4)/l11
    s = a(2, 2) - l21*l21
    if (s <= singular_pivot*a(2, 2)) return
    l22 = sqrt(s)
    l32 = (a(2, 3) - l31*l21)/l22
    l42 = (a(2, 4) - l41*l21)/l22
    s = a(3, 3) - l31*l31 - l32*l32
    if (s <= singular_pivot*a(3, 3)) return
    l33 = sqrt(s)
    l43 = (a(3, 4) - l41*l31 - l42*l32)/l33
    s = a(4, 4) - l41*l41 - l42*l42 - l43*l43
    if (s <= singular_pivot*a(4, 4)) return
    l44 = sqrt(s)
    det = (l11*l22*l33*l44)**2
  end function chol4_inline

  !> n uniform random points in [lo, hi], reproducible from seed.
  subroutine random_points(lo, hi, seed, p)
    real(wp), intent(in) :: lo(2), hi(2)
    integer, intent(in) :: seed
    real(wp), intent(out) :: p(:, :)
    integer :: n, k
    integer, allocatable :: s(:)
    call random_seed(size=n)
    allocate(s(n))
    s = [(seed + 7919*k, k = 1, n)]
    call random_seed(put=s)
    call random_number(p)
    do k = 1, 2
      p(k, :) = lo(k) + (hi(k) - lo(k))*p(k, :)
    end do
  end subroutine random_points

  !> The same points ordered by bin cell (row-major), to show what query order costs.
  subroutine sort_by_cell(c, p, ps)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: ps(:, :)
    real(wp), allocatable :: key(:)
    integer, allocatable :: order(:)
    integer :: i, ij(2), k
    allocate(key(size(p, 2)), order(size(p, 2)))
    do i = 1, size(p, 2)
      do k = 1, 2
        ij(k) = floor((p(k, i) - c%bins%lo(k))*c%bins%inv_cell(k))
      end do
      key(i) = real(ij(2), wp)*1.0e6_wp + real(ij(1), wp) + p(1, i)*1.0e-9_wp
    end do
    call sort_index(key, order)
    ps = p(:, order)
  end subroutine sort_by_cell

  !> Mean number of candidates the cell block visits, and of particles whose support
  !! covers the point (the work of one query).
  subroutine neighbour_counts(c, p, cand, hits)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: cand, hits
    integer(int64) :: nc, nh
    integer :: i, j, q, lo1, hi1, lo2, hi2
    real(wp) :: a
    nc = 0
    nh = 0
    do i = 1, size(p, 2)
      a = (p(1, i) - c%rmax(1) - c%bins%lo(1))*c%bins%inv_cell(1)
      if (a >= real(c%bins%nc(1), wp)) cycle
      lo1 = max(0, int(a))
      a = (p(1, i) + c%rmax(1) - c%bins%lo(1))*c%bins%inv_cell(1)
      if (a < 0.0_wp) cycle
      hi1 = min(c%bins%nc(1) - 1, int(a))
      a = (p(2, i) - c%rmax(2) - c%bins%lo(2))*c%bins%inv_cell(2)
      if (a >= real(c%bins%nc(2), wp)) cycle
      lo2 = max(0, int(a))
      a = (p(2, i) + c%rmax(2) - c%bins%lo(2))*c%bins%inv_cell(2)
      if (a < 0.0_wp) cycle
      hi2 = min(c%bins%nc(2) - 1, int(a))
      do j = lo2, hi2
        do q = c%bins%start(1 + c%bins%nc(1)*j + lo1), c%bins%start(2 + c%bins%nc(1)*j + hi1) - 1
          nc = nc + 1
          if (abs(c%x(1, q) - p(1, i)) < c%rho(1, q) .and. &
            abs(c%x(2, q) - p(2, i)) < c%rho(2, q)) nh = nh + 1
        end do
      end do
    end do
    cand = real(nc, wp)/real(size(p, 2), wp)
    hits = real(nh, wp)/real(size(p, 2), wp)
  end subroutine neighbour_counts

  !> Part B.
  subroutine accuracy()
    integer :: ir, ishape
    real(wp) :: dx, width(3, 3), rbuf(3, 3), spac(3, 3)
    integer :: nr, nt
    type(error_t), allocatable :: err
    real(wp), parameter :: lv(2, 6) = reshape([0.0_wp, 0.0_wp, 10.0_wp, 0.0_wp, &
      10.0_wp, 4.0_wp, 4.0_wp, 4.0_wp, 4.0_wp, 10.0_wp, 0.0_wp, 10.0_wp], [2, 6])*mm_
    character(len=*), parameter :: shapes(3) = [character(len=9) :: &
      'rectangle', 'l_shape', 'annulus']
    write(output_unit, '(/,a)') '## B. Accuracy: det(M) > eps_cr against the exact geometry'
    write(output_unit, '(a,es9.2,a)') '# eps_cr = ', eps_cr, &
      '; query grid spacing dx/8 over the body grown by 2 rho; distances in mm'
    write(output_unit, '(/,a)') '| shape | dx (mm) | particles | rho_buffer (mm) | '// &
      'inside, det<=eps | widest det>eps outside (mm) | / rho_buffer | '// &
      'nearest det<=eps outside (mm) | beyond buffer | min det inside | plateau |'
    write(output_unit, '(a)') '|---|---|---|---|---|---|---|---|---|---|---|'
    do ishape = 1, 3
      do ir = 1, 3
        block
        ! a fresh body per case: the generators expect an empty one
        type(body_t) :: b
        select case (ishape)
        case (1)
          dx = (1.0_wp/3.0_wp)/2.0_wp**(ir - 1)*mm_
          call make_rectangle(b, [0.0_wp, 0.0_wp], [5.0_wp*mm_, 60.0_wp*mm_], &
            [nint(5.0_wp*mm_/dx) + 1, nint(60.0_wp*mm_/dx) + 1], err)
          call check(err)
          call set_supports(b, [support_factor, support_factor])
        case (2)
          dx = 0.5_wp/2.0_wp**(ir - 1)*mm_
          call make_polygon(b, lv, [dx, dx], [0.0_wp, 0.0_wp], err)
          call check(err)
          call set_supports(b, [support_factor, support_factor])
        case (3)
          ! r in [5, 10] mm, theta in [0, 90] deg; r_mid dtheta = dr
          nr = 10*2**(ir - 1) + 1
          nt = 24*2**(ir - 1) + 1
          call make_annulus(b, [0.0_wp, 0.0_wp], 5.0_wp*mm_, 10.0_wp*mm_, 0.0_wp, &
            0.5_wp*pi, nr, nt, err)
          call check(err)
          call annulus_supports(b, 5.0_wp*mm_, 10.0_wp*mm_, 0.5_wp*pi, nr, nt)
          dx = b%spacing(1)
        end select
        call classify_case(b, trim(shapes(ishape)), dx, width(ir, ishape), &
          rbuf(ir, ishape))
        spac(ir, ishape) = dx
        end block
      end do
    end do
    write(output_unit, '(/,a)') '| shape | width ratio coarse/medium | medium/fine | '// &
      'width/dx (coarse, medium, fine) |'
    write(output_unit, '(a)') '|---|---|---|---|'
    do ishape = 1, 3
      write(output_unit, '(a,a,a,f6.2,a,f6.2,a,3f6.2,a)') '| ', trim(shapes(ishape)), &
        ' | ', width(1, ishape)/width(2, ishape), ' | ', width(2, ishape)/width(3, ishape), &
        ' | ', width(:, ishape)/spac(:, ishape), ' |'
      write(output_unit, '(a,a,a,f5.3,a,f5.3,a,a)') 'RESULT bench=accuracy_trend shape=', &
        trim(shapes(ishape)), ' width_ratio_c_m=', width(1, ishape)/width(2, ishape), &
        ' width_ratio_m_f=', width(2, ishape)/width(3, ishape), ' shrinks=', &
        merge('yes', 'no ', width(2, ishape) < width(1, ishape) .and. &
        width(3, ishape) < width(2, ishape))
    end do
  end subroutine accuracy

  !> The deck's rule for annulus sectors (bodies_m/build_body): rho_i = factor *
  !! max(dr, r_i dtheta), basis scale = factor * nominal spacing.
  subroutine annulus_supports(b, r0, r1, span, nr, nt)
    type(body_t), intent(inout) :: b
    real(wp), intent(in) :: r0, r1, span
    integer, intent(in) :: nr, nt
    real(wp), allocatable :: local(:)
    real(wp) :: dr, dt
    integer :: i
    dr = (r1 - r0)/real(nr - 1, wp)
    dt = span/real(nt - 1, wp)
    allocate(local(b%np))
    do i = 1, b%np
      local(i) = max(dr, norm2(b%x(:, i))*dt)
    end do
    call set_supports(b, [support_factor, support_factor], local)
  end subroutine annulus_supports

  !> Classify a grid around body b and print one table row; width and the buffer it must
  !! stay under come back (m).
  subroutine classify_case(b, shape, dx, width, rbuf)
    type(body_t), intent(inout) :: b
    character(len=*), intent(in) :: shape
    real(wp), intent(in) :: dx
    real(wp), intent(out) :: width, rbuf
    type(rk_cloud_t) :: c
    type(error_t), allocatable :: err
    type(buffer_stats_t) :: st
    real(wp), allocatable :: p(:, :), det(:), dist(:)
    integer, allocatable :: inside(:)
    real(wp) :: lo(2), hi(2), g, rmax(2), plateau, dmin
    integer :: n(2), i, j, k
    b%kid = kernel_cubic
    b%wshape = window_tensor
    b%bid = basis_bilinear
    call body_cloud(b, c, err)
    call check(err)
    rmax = maxval(b%rho, dim=2)
    ! eq. (50) with the largest support present (annulus supports grow with radius)
    rbuf = norm2(rmax)
    g = dx/8.0_wp
    lo = minval(b%x, dim=2) - 2.0_wp*rmax
    hi = maxval(b%x, dim=2) + 2.0_wp*rmax
    n = ceiling((hi - lo)/g) + 1
    allocate(p(2, n(1)*n(2)), det(n(1)*n(2)), dist(n(1)*n(2)), inside(n(1)*n(2)))
    k = 0
    do j = 1, n(2)
      do i = 1, n(1)
        k = k + 1
        p(:, k) = lo + g*real([i - 1, j - 1], wp)
      end do
    end do
    call omp_set_num_threads(2)
    call det_at_points(c, p, det)
    call classify(det, eps_cr, inside)
    call buffer_stats(b, p, inside, dist, st)
    plateau = body_plateau(b, c)
    dmin = minval(det, mask=dist <= 0.0_wp)
    width = st%max_outside_inside
    write(output_unit, '(a,a,a,f7.4,a,i6,a,f7.4,a,i0,a,f7.4,a,f5.3,a,f7.4,a,i0,a,es9.2,a,' &
      //'es9.2,a)') '| ', shape, ' | ', dx/mm_, ' | ', b%np, ' | ', rbuf/mm_, ' | ', &
      st%n_false_outside, ' | ', width/mm_, ' | ', width/rbuf, ' | ', &
      st%min_outside_outside/mm_, ' | ', count(inside == 1 .and. dist >= rbuf), ' | ', &
      dmin, ' | ', plateau, ' |'
    write(output_unit, '(a,a,a,es10.4,a,i0,a,i0,a,es10.4,a,es10.4,a,f5.3,a,i0,a,es9.3,a,a)') &
      'RESULT bench=accuracy shape=', shape, ' dx_m=', dx, ' np=', b%np, ' false_outside=', &
      st%n_false_outside, ' width_m=', width, ' rho_buffer_m=', rbuf, ' width_over_buffer=', &
      width/rbuf, ' beyond_buffer=', count(inside == 1 .and. dist >= rbuf), &
      ' min_det_inside=', dmin, ' ok=', merge('yes', 'no ', st%n_false_outside == 0 &
      .and. width < rbuf)
  end subroutine classify_case

  !> Command line: [--rounds N] (default 1) [--no-throughput] [--no-accuracy] [--no-3d].
  subroutine read_args(nround, do_throughput, do_accuracy, do_3d)
    integer, intent(out) :: nround
    logical, intent(out) :: do_throughput, do_accuracy, do_3d
    integer :: i, ios
    character(len=64) :: arg
    nround = 1
    do_throughput = .true.
    do_accuracy = .true.
    do_3d = .true.
    i = 1
    do while (i <= command_argument_count())
      call get_command_argument(i, arg)
      select case (trim(arg))
      case ('--rounds')
        i = i + 1
        call get_command_argument(i, arg)
        read(arg, *, iostat=ios) nround
        if (ios /= 0 .or. nround < 1) then
          write(error_unit, '(a)') 'bench_detect: --rounds needs a positive integer'
          error stop 2
        end if
      case ('--no-throughput')
        do_throughput = .false.
      case ('--no-accuracy')
        do_accuracy = .false.
      case ('--no-3d')
        do_3d = .false.
      case ('--only-3d')
        do_throughput = .false.
        do_accuracy = .false.
      case default
        write(error_unit, '(a)') 'bench_detect: unknown argument '''//trim(arg)// &
          '''; usage: bench_detect [--rounds N] [--no-throughput] [--no-accuracy] '// &
          '[--no-3d] [--only-3d]'
        error stop 2
      end select
      i = i + 1
    end do
  end subroutine read_args

  subroutine check(err)
    type(error_t), allocatable, intent(inout) :: err
    if (allocated(err)) then
      write(error_unit, '(a)') 'bench_detect: '//err%message
      error stop 1
    end if
  end subroutine check
end program bench_detect
