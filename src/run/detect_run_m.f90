!> The 'detect' mode: det(M) of one body on a query line, a grid and marked points, its
!! inside/outside classification, and the buffer-zone statistics, written to HDF5
!! (Examples 2.1 and 2.2, Figs. 2-7 and 11). Layout: doc/output.md.
module detect_run_m
  use omp_lib, only: omp_get_wtime, omp_get_max_threads
  use kinds_m, only: wp
  use errors_m, only: error_t, exit_run_failed
  use strings_m, only: itoa
  use deck_m, only: deck_t, detection_spec_t
  use body_m, only: body_t
  use rk_cloud_m, only: rk_cloud_t
  use detection_m, only: body_cloud, det_at_points, body_plateau, classify, buffer_stats, &
    buffer_stats_t, detection_threshold
  use hdf5_io_m, only: h5file_t, h5_close, h5_group, h5_write, h5_attr
  use run_output_m, only: write_header, write_bodies
  use output_path_m, only: output_path_t, output_open, output_commit
  use log_m, only: log_print
  implicit none
  private
  public :: run_detect

  !> A timed interval below this (s) counts as this much, so a rate is never a division
  !! by zero: a nanosecond, below what the wall clock resolves.
  real(wp), parameter :: clock_tick = 1.0e-9_wp

contains

  !> Evaluate, classify, log and write. bodies are built and checked already. The file is
  !! written under a temporary name and renamed onto &output file when it is complete
  !! (output_path_m); a failed write leaves it under the failed-run name, with exit code 1.
  subroutine run_detect(deck, bodies, err)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    type(detection_spec_t) :: d
    type(rk_cloud_t) :: c
    type(h5file_t) :: f
    type(output_path_t) :: path
    type(error_t), allocatable :: e2
    character(len=:), allocatable :: note
    character(len=160) :: line
    real(wp) :: plateau, threshold, t0
    integer :: k, kb, nd
    d = deck%detection
    nd = deck%run%ndim
    kb = 0
    do k = 1, size(bodies)
      if (bodies(k)%name == d%body) kb = k
    end do
    associate (b => bodies(kb))
      t0 = omp_get_wtime()
      call body_cloud(b, c, err)
      if (allocated(err)) return
      plateau = body_plateau(b, c)
      threshold = detection_threshold(d%eps_cr, d%eps_rel, plateau)
      call log_print('detect: body '''//trim(b%name)//''', '//itoa(b%np)// &
        ' particles, '//itoa(omp_get_max_threads())//' thread(s)')
      write(line, '(a,es12.5,a,es10.3,a,es10.3,a,es10.3)') &
        'detect: interior plateau det(M) = ', plateau, '; eps_cr = ', d%eps_cr, &
        ', eps_rel x plateau = ', d%eps_rel*plateau, '; threshold used = ', threshold
      call log_print(trim(line))
      call output_open(deck, .false., path, f, err)
      if (allocated(err)) return
      call write_header(f, deck, err)
      if (.not. allocated(err)) call write_bodies(f, bodies, deck, err)
      if (.not. allocated(err)) call h5_group(f, '/detection', err)
      if (.not. allocated(err)) call h5_attr(f, '/detection', 'body', trim(b%name), err)
      if (.not. allocated(err)) call h5_attr(f, '/detection', 'plateau', plateau, err)
      if (.not. allocated(err)) call h5_attr(f, '/detection', 'eps_cr', d%eps_cr, err)
      if (.not. allocated(err)) call h5_attr(f, '/detection', 'eps_rel', d%eps_rel, err)
      if (.not. allocated(err)) call h5_attr(f, '/detection', 'threshold', threshold, err)
      if (.not. allocated(err)) call h5_attr(f, '/detection', 'rho_buffer', &
        norm2(b%h(1:nd)), err)
      if (.not. allocated(err) .and. d%line_n > 0) call query_set(f, '/detection/line', b, c, &
        line_points(d, nd), threshold, err, line_param(d, nd))
      if (.not. allocated(err) .and. any(d%grid_n(1:nd) > 0)) call query_set(f, &
        '/detection/grid', b, c, grid_points(d, nd), threshold, err, grid_n=d%grid_n(1:nd), &
        d=d)
      if (.not. allocated(err) .and. d%npoints > 0) call query_set(f, '/detection/points', b, &
        c, d%points(1:nd, 1:d%npoints), threshold, err)
      call h5_close(f, e2)
      if (allocated(e2) .and. .not. allocated(err)) call move_alloc(e2, err)
      call output_commit(path, .not. allocated(err), note, e2)
      if (allocated(e2)) then
        if (allocated(err)) e2%message = err%message//'; '//e2%message
        call move_alloc(e2, err)
        return
      end if
      if (allocated(err)) then
        err%message = err%message//'; what was written is in '//note
        err%code = exit_run_failed
        return
      end if
      write(line, '(a,f8.3,a)') 'detect: done in ', omp_get_wtime() - t0, ' s'
      call log_print(trim(line))
    end associate
  end subroutine run_detect

  !> One query set: det, inside flag and signed distance, logged with its buffer statistics.
  subroutine query_set(f, g, b, c, p, threshold, err, s, grid_n, d)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: g
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:, :), threshold
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: s(:)
    integer, intent(in), optional :: grid_n(:)
    type(detection_spec_t), intent(in), optional :: d
    real(wp), allocatable :: det(:), dist(:)
    integer, allocatable :: inside(:)
    type(buffer_stats_t) :: st
    real(wp) :: t0, t1
    integer :: n, j
    character(len=200) :: line
    n = size(p, 2)
    allocate(det(n), dist(n), inside(n))
    t0 = omp_get_wtime()
    call det_at_points(c, p, det)
    t1 = omp_get_wtime() - t0
    call classify(det, threshold, inside)
    call buffer_stats(b, p, inside, dist, st)
    write(line, '(a,i0,a,f8.4,a,f8.2,a,i0,a)') 'detect: '//g//': ', n, &
      ' points in ', t1, ' s (', real(n, wp)/max(t1, clock_tick)/1.0e6_wp, &
      ' M/s), ', count(inside == 1), ' inside'
    call log_print(trim(line))
    if (b%geom%kind /= 0) then
      write(line, '(a,es10.3,a,es10.3,a,i0,a,i0)') &
        'detect:   buffer zone: farthest det > eps point outside at ', &
        st%max_outside_inside, ' m (rho = ', st%rho_buffer, ' m); points beyond rho: ', &
        st%n_beyond_buffer, '; interior points with det <= eps: ', st%n_false_outside
      call log_print(trim(line))
    end if
    call h5_group(f, g, err)
    if (.not. allocated(err)) call h5_write(f, g//'/x', p, 'm', err, 'query points (ndim, n)')
    if (.not. allocated(err)) call h5_write(f, g//'/det', det, '1', err, &
      'det(M) of the body at the query points (dimensionless)')
    if (.not. allocated(err)) call h5_write(f, g//'/inside', inside, '1', err, &
      '1 where det(M) > threshold')
    if (.not. allocated(err) .and. b%geom%kind /= 0) call h5_write(f, g//'/distance', dist, &
      'm', err, 'signed distance to the exact body boundary (< 0 inside)')
    if (.not. allocated(err)) call h5_attr(f, g, 'seconds', t1, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'max_outside_inside', &
      st%max_outside_inside, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'n_beyond_buffer', int(st%n_beyond_buffer), err)
    if (.not. allocated(err)) call h5_attr(f, g, 'n_false_outside', &
      int(st%n_false_outside), err)
    if (present(s) .and. .not. allocated(err)) call h5_write(f, g//'/s', s, 'm', err, &
      'distance along the line from line_from')
    if (present(grid_n) .and. present(d) .and. .not. allocated(err)) then
      call h5_attr(f, g, 'shape', real(grid_n, wp), err)
      do j = 1, size(grid_n)
        if (.not. allocated(err)) call h5_write(f, g//'/axis'//achar(iachar('0') + j), &
          axis(d%grid_lo(j), d%grid_hi(j), grid_n(j)), 'm', err, &
          'grid coordinates along direction '//itoa(j)//' (x fastest in /x and /det)')
      end do
    end if
  end subroutine query_set

  pure function axis(a, z, n) result(v)
    real(wp), intent(in) :: a, z
    integer, intent(in) :: n
    real(wp) :: v(n)
    integer :: i
    do i = 1, n
      v(i) = a + (z - a)*real(i - 1, wp)/real(max(n - 1, 1), wp)
    end do
  end function axis

  pure function line_points(d, nd) result(p)
    type(detection_spec_t), intent(in) :: d
    integer, intent(in) :: nd
    real(wp) :: p(nd, d%line_n)
    integer :: i
    do i = 1, d%line_n
      p(:, i) = d%line_from(1:nd) + (d%line_to(1:nd) - d%line_from(1:nd)) &
        *real(i - 1, wp)/real(d%line_n - 1, wp)
    end do
  end function line_points

  pure function line_param(d, nd) result(s)
    type(detection_spec_t), intent(in) :: d
    integer, intent(in) :: nd
    real(wp) :: s(d%line_n)
    integer :: i
    do i = 1, d%line_n
      s(i) = norm2(d%line_to(1:nd) - d%line_from(1:nd))*real(i - 1, wp)/real(d%line_n - 1, wp)
    end do
  end function line_param

  pure function grid_points(d, nd) result(p)
    type(detection_spec_t), intent(in) :: d
    integer, intent(in) :: nd
    real(wp), allocatable :: p(:, :)
    integer :: n(3), i, j, k, q
    n = 1
    n(1:nd) = d%grid_n(1:nd)
    allocate(p(nd, product(n)))
    q = 0
    do k = 1, n(3)
      do j = 1, n(2)
        do i = 1, n(1)
          q = q + 1
          p(1, q) = d%grid_lo(1) + (d%grid_hi(1) - d%grid_lo(1))*real(i - 1, wp) &
            /real(max(n(1) - 1, 1), wp)
          if (nd > 1) p(2, q) = d%grid_lo(2) + (d%grid_hi(2) - d%grid_lo(2)) &
            *real(j - 1, wp)/real(max(n(2) - 1, 1), wp)
          if (nd > 2) p(3, q) = d%grid_lo(3) + (d%grid_hi(3) - d%grid_lo(3)) &
            *real(k - 1, wp)/real(max(n(3) - 1, 1), wp)
        end do
      end do
    end do
  end function grid_points
end module detect_run_m
