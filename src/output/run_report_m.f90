!> What a dynamic run reports while it runs and when it ends: the record of the run (step,
!! time, counters, timers, contact events), the log lines, the history rows, the det(M)
!! fields of the contact pairs at snapshots (Figs. 9-10), and the summary on standard
!! output and in /summary. Layout of the file: doc/output.md.
module run_report_m
  use, intrinsic :: iso_fortran_env, only: output_unit
  use omp_lib, only: omp_get_wtime, omp_get_max_threads
  use kinds_m, only: wp, i64
  use errors_m, only: error_t
  use strings_m, only: itoa, rtoa
  use solid_m, only: solid_t
  use run_health_m, only: energies_t, fail_key_size
  use body_measures_m, only: measures_t, body_measures
  use contact_pair_m, only: contact_pair_t, contact_stats_t, contact_det_fields, detector_name, &
    contact_self_det, side_np_whole, &
    detector_det_m
  use hdf5_io_m, only: h5file_t, h5_group, h5_attr, h5_write, h5_write_rows
  use dynamic_output_m, only: history_names
  use stable_step_m, only: step_control_t, step_limit_text, step_smallest
  use subcycle_m, only: subcycle_record_t
  implicit none
  private
  public :: run_record_t, record_contact, log_header, log_line, history_row, &
    history_row_measured, &
    det_fields_out, report_summary, run_status, self_det_out

  !> The running record of a dynamic run.
  type :: run_record_t
    integer :: n = 0                      !< steps taken
    real(wp) :: t = 0.0_wp                !< time (s)
    real(wp) :: dt = 0.0_wp               !< the last step (s)
    type(step_control_t) :: step          !< the time-step policy and its record
    type(subcycle_record_t) :: sub        !< what subcycling did
    real(wp) :: t_end = 0.0_wp            !< the deck's end time (s)
    integer :: nsteps_est = 0             !< steps to t_end at the first step (for defaults)
    logical :: failed = .false.
    integer :: energy_over = 0            !< consecutive steps over the energy limit
    character(len=:), allocatable :: reason
    !> where the failure is in the serial run's order (run_health_m fail_key_size)
    real(wp) :: fail_key(fail_key_size) = huge(1.0_wp)
    integer(i64) :: node_steps = 0        !< nodes x steps over all solids
    integer(i64) :: point_steps = 0       !< integration points (triangles) x steps
    real(wp) :: wall0 = 0.0_wp            !< wall clock at the start (s)
    real(wp) :: t_loop = 0.0_wp, t_contact = 0.0_wp, t_output = 0.0_wp   !< timers (s)
    type(contact_stats_t) :: contact      !< what contact did in the last step
    real(wp) :: pen_max = 0.0_wp          !< deepest penetration left by a correction (m)
    real(wp) :: impulse = 0.0_wp          !< normal contact impulse since t = 0 (N s)
    real(wp) :: t_edge_first = -1.0_wp    !< first contact of the tracked edge node (s)
    real(wp) :: t_edge_sep = -1.0_wp      !< its last separation (s)
    logical :: edge_prev = .false.
  end type run_record_t

  !> A timed interval below this (s) counts as this much, so a rate or share is never a
  !! division by zero: a nanosecond, below what the wall clock resolves.
  real(wp), parameter :: clock_tick = 1.0e-9_wp

contains

  !> Keep what the step's contact did (c) in the record; t_new is the time at its end.
  subroutine record_contact(r, c, t_new)
    type(run_record_t), intent(inout) :: r
    type(contact_stats_t), intent(in) :: c
    real(wp), intent(in) :: t_new
    r%contact = c
    r%pen_max = max(r%pen_max, c%pen_after)
    r%impulse = r%impulse + c%force_normal*r%dt
    if (c%edge_in_contact .and. r%t_edge_first < 0.0_wp) r%t_edge_first = t_new
    if (r%edge_prev .and. .not. c%edge_in_contact) r%t_edge_sep = t_new
    r%edge_prev = c%edge_in_contact
  end subroutine record_contact

  subroutine log_header()
    write(output_unit, '(a)') 'dynamic:   cycle      time (s)     dt (s)       KE (J)'// &
      '     W_int (J)    W_plas (J)   W_ext (J)   W_cont (J)  residual  contacts  ETA (s)'
    flush(output_unit)
  end subroutine log_header

  subroutine log_line(r, en)
    type(run_record_t), intent(in) :: r
    type(energies_t), intent(in) :: en
    real(wp) :: eta, elapsed
    elapsed = omp_get_wtime() - r%wall0
    eta = 0.0_wp
    ! steps left at the current step (it shrinks as the bodies deform: an estimate)
    if (r%n > 0 .and. r%dt > 0.0_wp) &
      eta = elapsed/real(r%n, wp)*max(r%t_end - r%t, 0.0_wp)/r%dt
    write(output_unit, '(a,i9,es14.6,es11.3,6es13.4,i7,f9.1)') 'dynamic: ', r%n, r%t, r%dt, &
      en%ke, en%w_int, en%w_plastic, en%w_ext, en%w_contact, en%residual, &
      r%contact%n_contact, eta
    flush(output_unit)
  end subroutine log_line

  !> One history row (history_names): energies, contact and the measures of solid s.
  function history_row(r, en, s) result(row)
    type(run_record_t), intent(in) :: r
    type(energies_t), intent(in) :: en
    type(solid_t), intent(inout) :: s
    real(wp) :: row(size(history_names))
    row = history_row_measured(r, en, body_measures(s))
  end function history_row

  !> One history row (history_names) with the measures m of the first solid (taken by the
  !! caller: body_measures_part on ranks).
  function history_row_measured(r, en, m) result(row)
    type(run_record_t), intent(in) :: r
    type(energies_t), intent(in) :: en
    type(measures_t), intent(in) :: m
    real(wp) :: row(size(history_names))
    row = [real(r%n, wp), r%t, r%dt, r%step%dtc, en%ke, en%w_int, en%w_plastic, en%w_ext, &
      en%w_contact, &
      en%residual, real(r%contact%n_contact, wp), r%contact%force_normal, r%contact%radius, &
      r%contact%pen_after, m%length, m%foot_radius, r%impulse]
  end function history_row_measured

  !> /snapshots/<lab>/<body>/det_self of every self-contact pair's body: det(M) at each
  !! particle from the particles that are not its reference neighbours (contact_self_det).
  !! In a file opened with MPI-IO every rank writes its own particles' rows, collectively.
  subroutine self_det_out(f, lab, pairs, solids, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: lab
    type(contact_pair_t), intent(inout) :: pairs(:)
    type(solid_t), intent(in) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: det(:)
    integer, allocatable :: own(:)
    integer :: kp
    character(len=:), allocatable :: g
    do kp = 1, size(pairs)
      if (allocated(err)) return
      if (.not. pairs(kp)%self) cycle
      call contact_self_det(pairs(kp), solids, det, own, err)
      g = '/snapshots/'//lab//'/'//trim(pairs(kp)%side(1)%name)
      if (.not. allocated(err)) call h5_write_rows(f, g//'/det_self', det, own, &
        side_np_whole(pairs(kp)%side(1)), '1', err, &
        'det(M) at each particle from the particles that are not its neighbours in the '// &
        'reference configuration (self-contact of contact'//itoa(kp)//'): above '// &
        'det_self_threshold where faces of the body meet')
      if (.not. allocated(err)) call h5_attr(f, g, 'det_self_threshold', &
        pairs(kp)%side(2)%threshold, err)
    end do
  end subroutine self_det_out

  !> /snapshots/<lab>/det/contact<k>: det(M_master), det(M_slave) on the grid lo..hi with
  !! n points and det(M_master) at the slave's nodes.
  subroutine det_fields_out(f, lab, pairs, solids, lo, hi, n, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: lab
    type(contact_pair_t), intent(in) :: pairs(:)
    type(solid_t), intent(in) :: solids(:)
    real(wp), intent(in) :: lo(2), hi(2)
    integer, intent(in) :: n(2)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: dm(:), ds(:), dms(:)
    integer :: kp
    character(len=:), allocatable :: g
    call h5_group(f, '/snapshots/'//lab//'/det', err)
    do kp = 1, size(pairs)
      if (allocated(err)) return
      allocate(dm(product(n)), ds(product(n)), dms(pairs(kp)%side(1)%np))
      call contact_det_fields(pairs(kp), solids, lo, hi, n, dm, ds, dms, err)
      g = '/snapshots/'//lab//'/det/contact'//itoa(kp)
      if (.not. allocated(err)) call h5_group(f, g, err)
      if (.not. allocated(err)) call h5_write(f, g//'/master', reshape(dm, n), '1', err, &
        'det(M) of the master on the grid (axis1 fastest)')
      if (.not. allocated(err)) call h5_write(f, g//'/slave', reshape(ds, n), '1', err, &
        'det(M) of the slave (current positions, reference volumes) on the grid')
      if (.not. allocated(err)) call h5_write(f, g//'/master_at_slave', dms, '1', err, &
        'det(M_master) at the slave particles (0 outside the master box)')
      if (.not. allocated(err)) call h5_write(f, g//'/axis1', grid_axis(1), 'm', err, &
        'grid coordinates along x1')
      if (.not. allocated(err)) call h5_write(f, g//'/axis2', grid_axis(2), 'm', err, &
        'grid coordinates along x2')
      if (.not. allocated(err)) call h5_attr(f, g, 'threshold', pairs(kp)%side(2)%threshold, &
        err)
      if (.not. allocated(err)) call h5_attr(f, g, 'master_plateau', &
        pairs(kp)%side(2)%plateau, err)
      deallocate(dm, ds, dms)
    end do
  contains
    function grid_axis(k) result(a)
      integer, intent(in) :: k
      real(wp), allocatable :: a(:)
      integer :: i
      allocate(a(n(k)))
      do i = 1, n(k)
        a(i) = lo(k) + (hi(k) - lo(k))*real(i - 1, wp)/real(n(k) - 1, wp)
      end do
    end function grid_axis
  end subroutine det_fields_out

  function run_status(r) result(st)
    type(run_record_t), intent(in) :: r
    character(len=:), allocatable :: st
    if (r%failed) then
      st = 'failed'
    else if (r%t < r%t_end - 0.5_wp*r%dt) then
      st = 'stopped at max_steps'
    else
      st = 'completed'
    end if
  end function run_status

  !> Shares of the time loop spent in kinematics, material update and internal force.
  function time_shares(r, solids) result(share)
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(in) :: solids(:)
    real(wp) :: share(3)
    integer :: k
    share = 0.0_wp
    do k = 1, size(solids)
      share = share + solids(k)%acc%wall
    end do
    share = share/max(r%t_loop, clock_tick)
  end function time_shares

  !> The summary: on standard output and as attributes of /summary in f. bm: each solid's
  !! measures (body_measures; on MPI ranks from the parts, the same values).
  subroutine report_summary(f, r, en, pairs, solids, bm, files, err)
    type(h5file_t), intent(in) :: f
    type(run_record_t), intent(in) :: r
    type(energies_t), intent(in) :: en
    type(contact_pair_t), intent(in) :: pairs(:)
    type(solid_t), intent(inout) :: solids(:)
    type(measures_t), intent(in) :: bm(:)
    character(len=*), intent(in) :: files
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    real(wp) :: wall, rate, sh(3), tl, dts, ts
    logical :: landed
    type(measures_t) :: m
    character(len=:), allocatable :: g, units, eunit
    ! energies per unit thickness in plane strain, of the whole revolution in axisymmetry
    eunit = 'J/m'
    if (size(solids) > 0) then
      if (solids(1)%t%axisym) eunit = 'J'
    end if
    wall = omp_get_wtime() - r%wall0
    tl = max(r%t_loop, clock_tick)
    rate = real(r%node_steps, wp)/tl
    sh = time_shares(r, solids)
    ! /summary: one named attribute per value, and in each group an attribute 'units'
    ! ("name=unit; ...") that gives every value's unit (doc/output.md)
    call h5_group(f, '/summary', err)
    g = '/summary'
    units = ''
    call put_s('status', run_status(r))
    call put_s('failure', r%reason)
    call put_i('steps', r%n, '1')
    call put_r('time', r%t, 's')
    call put_r('dt', r%dt, 's')
    call step_smallest(r%step, dts, ts, landed)
    call put_r('dt_min', dts, 's')
    call put_r('dt_max', r%step%dt_max, 's')
    call put_r('dt_min_time', ts, 's')
    call put_i('dt_adaptive', merge(1, 0, r%step%adaptive), '1')
    call put_r('dt_critical', r%step%dtc0, 's')
    call put_r('dt_critical_min', r%step%dtc_min, 's')
    call put_s('dt_critical_min_at', step_limit_text(r%step, solids, .true.))
    call put_i('dt_fixed_over_critical_steps', r%step%n_over, '1')
    call put_r('wall_time', wall, 's')
    call put_i('threads', omp_get_max_threads(), '1')
    call put_r('particle_steps_per_second', rate, '1/s')
    call put_r('point_steps_per_second', real(r%point_steps + r%sub%fine_evals, wp)/tl, '1/s')
    ! &solver subcycle: steps split, their sub-steps, the fine points' updates in the
    ! sub-steps but the last, and what those sub-steps would have cost unsplit
    call put_i('subcycled_steps', int(r%sub%steps), '1')
    call put_i('substeps', int(r%sub%substeps), '1')
    call put_i('substeps_max', r%sub%m_max, '1')
    call put_r('substep_point_updates', real(r%sub%fine_evals, wp), '1')
    call put_r('substep_point_updates_unsplit', real(r%sub%uniform_evals, wp), '1')
    call put_r('energy_residual', en%residual, eunit)
    call put_r('energy_scale', en%scale, eunit)
    call put_r('kinetic_energy', en%ke, eunit)
    call put_r('internal_work', en%w_int, eunit)
    call put_r('plastic_dissipation', en%w_plastic, eunit)
    call put_r('contact_work', en%w_contact, eunit)
    call put_r('max_remaining_penetration', r%pen_max, 'm')
    call put_r('edge_first_contact_time', r%t_edge_first, 's')
    call put_r('edge_separation_time', r%t_edge_sep, 's')
    call close_group()
    ! where the time loop's wall time went
    call open_group('/summary/timing')
    call put_r('time_loop', r%t_loop, 's')
    call put_r('kinematics', sh(1), 's')
    call put_r('material', sh(2), 's')
    call put_r('internal_force', sh(3), 's')
    call put_r('contact', r%t_contact, 's')
    call put_r('snapshots', r%t_output, 's')
    call close_group()
    if (.not. allocated(err)) call h5_group(f, '/summary/contacts', err)
    do k = 1, size(pairs)
      call open_group('/summary/contacts/contact'//itoa(k))
      associate (p => pairs(k), c => pairs(k)%count)
        call put_s('master', trim(p%side(2)%name))
        call put_s('slave', trim(p%side(1)%name))
        call put_s('detector', detector_name(p%detector))
        call put_i('self', merge(1, 0, p%self), '1')
        call put_i('compare_detectors', merge(1, 0, p%compare), '1')
        call put_r('screened', real(c%screened, wp), '1')
        call put_r('evaluated', real(c%evaluated, wp), '1')
        call put_r('detected', real(c%detected, wp), '1')
        call put_r('contacts', real(c%contacts, wp), '1')
        call put_r('detected_max_per_step', real(c%detected_max, wp), '1')
        call put_r('skipped_far', real(c%skipped, wp), '1')
        call put_r('detect_time', c%t_detect, 's')
        call put_r('pair_time', c%t_pair, 's')
        call put_r('compare_det', real(c%cmp_det, wp), '1')
        call put_r('compare_gap', real(c%cmp_gap, wp), '1')
        call put_r('compare_buffer', real(c%cmp_buffer, wp), '1')
        call put_r('compare_missed', real(c%cmp_missed, wp), '1')
        call put_r('compare_det_max', real(c%cmp_det_max, wp), '1')
        call put_r('compare_gap_max', real(c%cmp_gap_max, wp), '1')
        call put_r('buffer_gap_mean', c%buffer_gap_sum/real(max(c%cmp_buffer, 1_i64), wp), 'm')
        call put_r('buffer_gap_max', c%buffer_gap_max, 'm')
        if (p%self .and. p%side(1)%ndim == 3) call put_r('self_unsure', &
          real(c%self_unsure, wp), '1')
      end associate
      call close_group()
    end do
    if (.not. allocated(err)) call h5_group(f, '/summary/bodies', err)
    do k = 1, size(solids)
      m = bm(k)
      call open_group('/summary/bodies/'//trim(solids(k)%name))
      call put_r('length', m%length, 'm')
      call put_r('width', m%width, 'm')
      call put_r('foot_radius', m%foot_radius, 'm')
      if (solids(k)%t%dims%ndim == 3) call put_r('depth', m%extent(2), 'm')
      call put_r('max_epsbar', m%max_epsbar, '1')
      call put_r('quiet_point_steps_skipped', real(solids(k)%acc%quiet_skipped, wp), '1')
      call close_group()
    end do
    call summary_log(r, en, pairs, solids, bm, files, wall, rate, sh, tl)
  contains
    subroutine open_group(path)
      character(len=*), intent(in) :: path
      g = path
      units = ''
      if (.not. allocated(err)) call h5_group(f, g, err)
    end subroutine open_group
    !> The group's 'units' attribute: "name=unit; ..." for every numeric value in it.
    subroutine close_group()
      if (.not. allocated(err)) call h5_attr(f, g, 'units', units, err)
    end subroutine close_group
    subroutine note_unit(name, unit)
      character(len=*), intent(in) :: name, unit
      if (len(units) > 0) units = units//'; '
      units = units//name//'='//unit
    end subroutine note_unit
    subroutine put_r(name, val, unit)
      character(len=*), intent(in) :: name, unit
      real(wp), intent(in) :: val
      if (.not. allocated(err)) call h5_attr(f, g, name, val, err)
      call note_unit(name, unit)
    end subroutine put_r
    subroutine put_i(name, val, unit)
      character(len=*), intent(in) :: name, unit
      integer, intent(in) :: val
      if (.not. allocated(err)) call h5_attr(f, g, name, val, err)
      call note_unit(name, unit)
    end subroutine put_i
    subroutine put_s(name, val)
      character(len=*), intent(in) :: name, val
      if (.not. allocated(err)) call h5_attr(f, g, name, val, err)
    end subroutine put_s
  end subroutine report_summary

  !> The summary's lines in the log: steps, rates, steps taken, energy, skipping, contact,
  !! the bodies' measures, where the time loop's time went (wall, rate, sh, tl: as
  !! report_summary measured them).
  subroutine summary_log(r, en, pairs, solids, bm, files, wall, rate, sh, tl)
    type(run_record_t), intent(in) :: r
    type(energies_t), intent(in) :: en
    type(contact_pair_t), intent(in) :: pairs(:)
    type(solid_t), intent(inout) :: solids(:)
    type(measures_t), intent(in) :: bm(:)
    character(len=*), intent(in) :: files
    real(wp), intent(in) :: wall, rate, sh(3), tl
    integer :: k
    type(measures_t) :: m
    real(wp) :: dts, ts
    logical :: landed
    write(output_unit, '(a,i0,a,es12.5,a,f9.2,a,f7.2,a,es10.3,a,es10.3,a)') 'summary: ', &
      r%n, ' steps to t = ', r%t, ' s in ', wall, ' s wall (set-up ', wall - r%t_loop, &
      ' s), ', rate, ' particle-steps/s (nodes), ', real(r%point_steps + r%sub%fine_evals, &
      wp)/tl, ' point-steps/s (integration points) in the time loop'
    if (r%sub%steps > 0) write(output_unit, '(a,i0,a,i0,a,i0,a,f6.2,a)') 'summary: '// &
      'subcycle: ', r%sub%steps, ' steps split into ', r%sub%substeps, ' sub-steps (at '// &
      'most ', r%sub%m_max, '); the fine points'' updates in them cost ', 100.0_wp* &
      real(r%sub%fine_evals, wp)/real(max(r%sub%uniform_evals, 1_i64), wp), &
      '% of whole-body sub-steps'
    call step_smallest(r%step, dts, ts, landed)
    write(output_unit, '(a,es10.3,a,es10.3,a,es10.3,a,es10.3,a,es10.3,a)') 'summary: dt ', &
      dts, ' to ', r%step%dt_max, ' s (smallest at t = ', ts, ' s'//trim(merge( &
      ', every step landed on an output time', '                                     ', &
      landed))//'); critical step ', r%step%dtc0, ' s at t = 0, smallest ', r%step%dtc_min, &
      ' s, set by '//step_limit_text(r%step, solids, .true.)// &
      merge(' (dt followed it)', ' (dt fixed)      ', r%step%adaptive)
    if (r%step%n_over > 0) write(output_unit, '(a,i0,a)') 'summary: warning: the fixed '// &
      'dt exceeded the critical step estimate in ', r%step%n_over, ' steps; dt = 0 lets '// &
      'the step follow the deformation'
    write(output_unit, '(a,es11.4,a,es11.4,a,es10.3)') 'summary: energy residual ', &
      en%residual, ' J of scale ', en%scale, ' J: relative ', en%residual/max(en%scale, &
      tiny(1.0_wp))
    do k = 1, size(solids)
      if (solids(k)%acc%quiet_skipped > 0) write(output_unit, '(a,i0,a,f5.1,a)') 'summary: '// &
        'body '''//trim(solids(k)%name)//''': skip_quiet: ', solids(k)%acc%quiet_skipped, &
        ' point-steps (', 100.0_wp*real(solids(k)%acc%quiet_skipped, wp)/real(max(r%n + 1, 1)* &
        max(solids(k)%nq, 1), wp), '%) skipped: points still in the uniform initial motion'
    end do
    do k = 1, size(pairs)
      write(output_unit, '(a,4(i0,a))') 'summary: contact '//itoa(k)//': ', &
        pairs(k)%count%screened, ' particles screened, ', pairs(k)%count%evaluated, &
        trim(merge(' det(M) evaluations,', ' segment searches,  ', &
        pairs(k)%detector == detector_det_m))//' ', pairs(k)%count%detected, ' detections, ', &
        pairs(k)%count%contacts, ' contact forces'
      write(output_unit, '(a,i0,a,f9.3,a)') 'summary: contact '//itoa(k)//': detector '// &
        detector_name(pairs(k)%detector)//', at most ', pairs(k)%count%detected_max, &
        ' particles flagged in one step, ', pairs(k)%count%t_detect, ' s in detection, '// &
        trim(rtoa(pairs(k)%count%t_pair))//' s in the pair''s whole correction'
      if (pairs(k)%side(1)%skip_far) write(output_unit, '(a,i0,a,f5.1,a)') 'summary: '// &
        'contact '//itoa(k)//': skip_far: ', pairs(k)%count%skipped, ' screenings ('// &
        '', 100.0_wp*real(pairs(k)%count%skipped, wp)/real(max(pairs(k)%count%screened, &
        1_i64), wp), '%) skipped: '//skip_reason(pairs(k)%self)
      if (pairs(k)%self .and. pairs(k)%side(1)%ndim == 3) write(output_unit, '(a,i0,a)') &
        'summary: contact '//itoa(k)//': self-contact: ', pairs(k)%count%self_unsure, &
        ' flags with g < 0 left without contact, their sign not sure (the closest '// &
        'point''s edge or vertex borders a reference neighbour''s facet)'
      if (.not. pairs(k)%compare) cycle
      associate (c => pairs(k)%count)
        write(output_unit, '(a,6(i0,a),es10.3,a,es10.3,a)') 'summary: contact '//itoa(k)// &
          ': detectors compared: det(M) > threshold ', c%cmp_det, ' (at most ', &
          c%cmp_det_max, ' in a step), gap < 0 ', c%cmp_gap, ' (at most ', c%cmp_gap_max, &
          '); buffer zone (det(M) flags, g >= 0) ', c%cmp_buffer, ', missed by det(M) ', &
          c%cmp_missed, '; buffer-zone gap mean ', c%buffer_gap_sum/real(max(c%cmp_buffer, &
          1_i64), wp), ' m, largest ', c%buffer_gap_max, ' m'
      end associate
    end do
    if (size(pairs) > 0) write(output_unit, '(a,es10.3,a,es11.4,a,es11.4,a)') &
      'summary: largest penetration left after a correction ', r%pen_max, ' m; edge '// &
      'particle: first contact ', r%t_edge_first, ' s, separation ', r%t_edge_sep, &
      ' s (-1: never)'
    do k = 1, size(solids)
      m = bm(k)
      if (solids(k)%t%axisym) then
        ! a body of revolution: the Taylor bar's measures (length along the axis, the
        ! largest radius, the foot's radius within one spacing of its lowest point)
        write(output_unit, '(a,es12.5,a,es12.5,a,es12.5,a,f8.4)') 'summary: body '''// &
          trim(solids(k)%name)//''': length (z extent) ', m%length, ' m, width (r extent) ', &
          m%width, ' m, foot radius ', m%foot_radius, ' m, max epsbar ', m%max_epsbar
      else if (solids(k)%t%dims%ndim == 3) then
        write(output_unit, '(a,3(es12.5,a),es12.5,a,f8.4)') 'summary: body '''// &
          trim(solids(k)%name)//''': extent ', m%extent(1), ' m in x, ', m%extent(2), &
          ' m in y, ', m%extent(3), ' m in z, foot radius (from the z axis) ', &
          m%foot_radius, ' m, max epsbar ', m%max_epsbar
      else
        write(output_unit, '(a,es12.5,a,es12.5,a,f8.4)') 'summary: body '''// &
          trim(solids(k)%name)//''': extent ', m%width, ' m in x, ', m%length, &
          ' m in y, max epsbar ', m%max_epsbar
      end if
    end do
    write(output_unit, '(a,f8.2,a,6(a,f5.1,a))') 'summary: time loop ', r%t_loop, ' s: ', &
      'kinematics ', 100.0_wp*sh(1), '%, ', 'material ', 100.0_wp*sh(2), '%, ', &
      'internal force ', 100.0_wp*sh(3), '%, ', 'contact ', 100.0_wp*r%t_contact/tl, '%, ', &
      'snapshots ', 100.0_wp*r%t_output/tl, '%, ', 'rest ', &
      100.0_wp*(1.0_wp - sum(sh) - (r%t_contact + r%t_output)/tl), '%'
    write(output_unit, '(a)') 'summary: wrote '//files
    flush(output_unit)
  end subroutine summary_log

  !> What the skipped screenings of a pair could not have done.
  pure function skip_reason(self) result(why)
    logical, intent(in) :: self
    character(len=:), allocatable :: why
    if (self) then
      why = 'surface particles that no non-neighbour could have reached'
    else
      why = 'particles that could not have reached the master''s box'
    end if
  end function skip_reason
end module run_report_m
