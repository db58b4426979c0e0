!> The explicit central-difference driver of a dynamic run, eqs. (62)-(64):
!!   u_{n+1} = u_n + dt v_n + dt^2/2 a_n                      (64)
!!   a_{n+1} = M^-1 (f_ext - f_int(u_{n+1}))                  (62)
!!   v_{n+1} = v_n + dt/2 (a_n + a_{n+1})                     (63)
!! with the row-sum lumped mass (70). Each step: predict, [contact], internal forces,
!! update, energy balance, guards, log, output. A run that goes unstable (non-finite
!! values, J <= 0, energy residual above the deck's tolerance) stops with a diagnostic
!! snapshot and exit code 1, keeping everything written so far.
module explicit_driver_m
  use, intrinsic :: iso_fortran_env, only: output_unit
  use omp_lib, only: omp_get_wtime, omp_get_max_threads
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error, exit_run_failed
  use strings_m, only: itoa, rtoa
  use deck_m, only: deck_t
  use body_m, only: body_t
  use tl_body_m, only: tl_body_t, tl_body_init, tl_body_forces, tl_apply_bc
  use tl_kinematics_m, only: physical_positions
  use stable_step_m, only: critical_step, spacing_step
  use hdf5_io_m, only: h5file_t, h5_create, h5_close, h5_group, h5_attr, h5_flush
  use run_output_m, only: write_header, write_bodies
  use dynamic_output_m, only: history_t, history_create, history_push, history_flush, &
    snapshot_write, xdmf_write, history_names
  use contact_pair_m, only: contact_pair_t, contact_pairs_init, contact_correct, &
    contact_det_fields
  use hdf5_io_m, only: h5_write
  implicit none
  private
  public :: run_dynamic

  !> Steps before the energy guard is armed (see the time loop).
  integer, parameter :: energy_warmup = 20

  !> Energy totals over the bodies (J; J/m in plane strain).
  type :: energies_t
    real(wp) :: ke = 0.0_wp, ke0 = 0.0_wp, w_int = 0.0_wp, w_plastic = 0.0_wp
    real(wp) :: w_ext = 0.0_wp, w_contact = 0.0_wp, residual = 0.0_wp, scale = 0.0_wp
  end type energies_t

contains

  !> Run the deck's dynamic problem. bodies are built and checked already.
  subroutine run_dynamic(deck, bodies, err)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    type(tl_body_t), allocatable :: tbs(:)
    type(contact_pair_t), allocatable :: pairs(:)
    type(h5file_t) :: f
    type(history_t) :: hist
    type(energies_t) :: en
    character(len=8), allocatable :: labels(:)
    real(wp), allocatable :: snap_t(:)
    character(len=:), allocatable :: reason, xdmf
    real(wp) :: dt, t, dtc, dts, wall0, wall, twrite
    integer :: k, ndef, n, nsnap_done, log_every, hist_every, nsteps_est, bad_q, kb
    logical :: axisym, failed
    real(wp) :: bad_j, pen_max, t_edge_first, t_edge_sep, fc_step, rad_step, pen_step
    integer(i64) :: psteps
    integer :: nc_step
    logical :: edge_prev
    real(wp) :: t_contact, t_output, t_loop0, t_loop, tw, impulse
    wall0 = omp_get_wtime()
    axisym = deck%run%geometry == 'axisymmetric'
    ndef = count(deck%bodies(1:deck%nbodies)%role == 'deformable')
    allocate(tbs(ndef))
    n = 0
    do k = 1, deck%nbodies
      if (deck%bodies(k)%role /= 'deformable') cycle
      n = n + 1
      call tl_body_init(deck, k, bodies(k), axisym, tbs(n), err)
      if (allocated(err)) return
      write(output_unit, '(a)') 'dynamic: body '''//trim(bodies(k)%name)//''': '// &
        itoa(tbs(n)%np)//' particles, '//itoa(tbs(n)%nq)//' integration points ('// &
        trim(deck%bodies(k)%integration)//'), material '''// &
        trim(deck%materials(deck%bodies(k)%imat)%name)//''' ('// &
        tbs(n)%mat%model_name()//'), mass '//rtoa(tbs(n)%t%total_mass)//' kg'// &
        merge('/m', '  ', .not. axisym)
    end do
    if (ndef == 0) then
      call set_error(err, "deck '"//deck%path//"': mode = 'dynamic' needs at least one "// &
        "deformable body (role = 'deformable')")
      return
    end if
    ! time step: fixed, or cfl x the critical step of the stiffest body
    dtc = huge(1.0_wp)
    dts = huge(1.0_wp)
    do k = 1, ndef
      dtc = min(dtc, critical_step(tbs(k)))
      dts = min(dts, spacing_step(tbs(k)))
    end do
    if (deck%solver%dt > 0.0_wp) then
      dt = deck%solver%dt
      write(output_unit, '(a,es10.3,a,es10.3,a,es10.3,a,f6.3,a)') 'dynamic: dt = ', dt, &
        ' s fixed by the deck; critical step 2/omega_max = ', dtc, ' s (h_min/c_d = ', dts, &
        ' s): dt is ', dt/dtc, ' of critical'
    else
      dt = deck%solver%cfl*dtc
      write(output_unit, '(a,es10.3,a,f5.2,a,es10.3,a,es10.3,a)') 'dynamic: dt = ', dt, &
        ' s = cfl ', deck%solver%cfl, ' x critical step 2/omega_max = ', dtc, &
        ' s (power iteration; h_min/c_d = ', dts, ' s)'
    end if
    if (dt > dtc) write(output_unit, '(a)') 'dynamic: warning: dt exceeds the estimated '// &
      'critical step; the run is likely to go unstable'
    call contact_pairs_init(deck, bodies, tbs, axisym, pairs, err)
    if (allocated(err)) return
    do k = 1, size(pairs)
      write(output_unit, '(a,es10.3,a,es10.3,a,es10.3,a,i0,a,f5.2,a)') 'contact: master '''// &
        trim(bodies(pairs(k)%side(2)%ibody)%name)//''' ('// &
        trim(merge('deformable', 'rigid     ', pairs(k)%both_ways))//', det(M) plateau ', &
        pairs(k)%side(2)%plateau, '), slave '''//trim(bodies(pairs(k)%side(1)%ibody)%name)// &
        ''': threshold ', pairs(k)%side(2)%threshold, ' (eps_cr ', pairs(k)%eps_cr, '), ', &
        pairs(k)%side(2)%surface%nseg, ' surface segments, mu = ', pairs(k)%mu, &
        trim(merge('; detection both ways (eq. 28)', '                              ', &
        pairs(k)%both_ways))
    end do
    do k = 1, size(pairs)
      write(output_unit, '(a,es10.3,a)') 'contact: det(M_master) at its surface particles '// &
        '(median) ', pairs(k)%side(2)%surface_det, trim(merge( &
        '; warning: the threshold is above it, shallow penetrations go undetected', &
        '                                                                        ', &
        pairs(k)%side(2)%threshold > pairs(k)%side(2)%surface_det))
    end do
    pen_max = 0.0_wp
    impulse = 0.0_wp
    t_edge_first = -1.0_wp
    t_edge_sep = -1.0_wp
    edge_prev = .false.
    nc_step = 0
    fc_step = 0.0_wp
    rad_step = 0.0_wp
    pen_step = 0.0_wp
    nsteps_est = ceiling(deck%solver%t_end/dt - 1.0e-9_wp)
    log_every = deck%solver%log_every
    if (log_every == 0) log_every = max(1, nsteps_est/50)
    ! a history row costs about one pass over the particles (physical positions for the
    ! body's extent): by default one row every 10 steps, at most about 1000 rows
    hist_every = deck%solver%history_every
    if (hist_every == 0) hist_every = max(1, min(log_every, max(10, nsteps_est/1000)))
    ! output
    call h5_create(f, trim(deck%output%file), err)
    if (allocated(err)) return
    call write_header(f, deck, err)
    if (.not. allocated(err)) call write_bodies(f, bodies, deck, err)
    if (.not. allocated(err)) call h5_group(f, '/snapshots', err)
    if (.not. allocated(err)) call history_create(f, hist, .not. axisym, err)
    if (allocated(err)) return
    xdmf = trim(deck%output%file)
    xdmf = xdmf(1:index(xdmf, '.', back=.true.) - 1)//'.xdmf'
    allocate(labels(0), snap_t(0))
    ! initial state: forces at u = 0
    do k = 1, ndef
      call tl_body_forces(tbs(k), dt, bad_q, bad_j)
      call tl_apply_bc(tbs(k))
    end do
    call energy_totals(tbs, en)
    t = 0.0_wp
    n = 0
    nsnap_done = 0
    call snapshots_due()
    call history_push(hist, history_row())
    write(output_unit, '(a)') 'dynamic:   cycle      time (s)     dt (s)       KE (J)'// &
      '     W_int (J)    W_plas (J)   W_ext (J)   W_cont (J)  residual  contacts  ETA (s)'
    call log_line()
    failed = .false.
    reason = ''
    psteps = 0
    t_contact = 0.0_wp
    t_output = 0.0_wp
    t_loop0 = omp_get_wtime()
    do while (t < deck%solver%t_end - 0.5_wp*dt .and. n < deck%solver%max_steps)
      do k = 1, ndef
        call predict_body(tbs(k), dt)
      end do
      tw = omp_get_wtime()
      call contact_step()
      t_contact = t_contact + (omp_get_wtime() - tw)
      do k = 1, ndef
        call finish_body(tbs(k), dt, bad_q, bad_j)
        psteps = psteps + tbs(k)%np
        if (bad_q > 0 .and. .not. failed) then
          failed = .true.
          kb = tbs(k)%ibody
          reason = 'step '//itoa(n + 1)//', body '''//trim(bodies(kb)%name)// &
            ''', integration point '//itoa(bad_q)//' (particle '//itoa(tbs(k)%t%owner(bad_q))// &
            '): J = '//rtoa(bad_j)//' (must stay > 0) or non-finite stress'
        end if
        if (.not. failed .and. .not. all(abs(tbs(k)%d) < huge(1.0_wp) .and. &
          abs(tbs(k)%v) < huge(1.0_wp))) then
          failed = .true.
          reason = 'step '//itoa(n + 1)//', body '''//trim(bodies(tbs(k)%ibody)%name)// &
            ''': non-finite displacement or velocity (particle '// &
            itoa(first_bad(tbs(k)))//')'
        end if
      end do
      t = t + dt
      n = n + 1
      call energy_totals(tbs, en)
      ! the energy guard watches for growth: an impulsive start (a velocity jump at t = 0)
      ! leaves a one-time residual of order dt that is large against the small energies of
      ! the first steps, so the check starts after a warm-up of 20 steps
      if (.not. failed .and. n > energy_warmup .and. &
        abs(en%residual) > deck%solver%energy_tol*en%scale) then
        failed = .true.
        reason = 'step '//itoa(n)//': energy residual '//rtoa(en%residual)//' exceeds '// &
          'energy_tol x energy scale = '//rtoa(deck%solver%energy_tol*en%scale)//'; '// &
          fastest_particle(tbs, bodies)
      end if
      if (mod(n, hist_every) == 0 .or. failed) call history_push(hist, history_row())
      if (mod(n, log_every) == 0 .or. failed) call log_line()
      if (failed) exit
      tw = omp_get_wtime()
      call snapshots_due()
      t_output = t_output + (omp_get_wtime() - tw)
      if (allocated(err)) return
    end do
    t_loop = omp_get_wtime() - t_loop0
    wall = omp_get_wtime() - wall0
    if (failed) then
      write(output_unit, '(a)') 'dynamic: FAILED at '//reason
      call snapshot_write(f, 'failure', t, n, bodies, tbs, err)
      labels = [character(len=8) :: labels, 'failure']
      snap_t = [snap_t, t]
      call xdmf_write(xdmf, basename(trim(deck%output%file)), labels, snap_t, bodies, tbs)
    else if (mod(n, hist_every) /= 0) then
      call history_push(hist, history_row())
    end if
    if (.not. allocated(err)) call history_flush(f, hist, err)
    if (.not. allocated(err)) call write_summary()
    call h5_close(f, err)
    write(output_unit, '(a,i0,a,es12.5,a,f9.2,a,f7.2,a,es10.3,a)') 'summary: ', n, &
      ' steps to t = ', t, ' s in ', wall, ' s wall (set-up ', wall - t_loop, ' s), ', &
      real(psteps, wp)/max(t_loop, 1.0e-9_wp), ' particle-steps/s in the time loop'
    write(output_unit, '(a,es11.4,a,es11.4,a,es10.3)') 'summary: energy residual ', &
      en%residual, ' J of scale ', en%scale, ' J: relative ', en%residual/max(en%scale, &
      tiny(1.0_wp))
    do k = 1, size(pairs)
      write(output_unit, '(a,4(i0,a))') 'summary: contact '//itoa(k)//': ', &
        pairs(k)%count%screened, ' particles screened, ', pairs(k)%count%evaluated, &
        ' det(M) evaluations, ', pairs(k)%count%detected, ' detections, ', &
        pairs(k)%count%contacts, ' contact forces'
    end do
    if (size(pairs) > 0) write(output_unit, '(a,es10.3,a,es11.4,a,es11.4,a)') &
      'summary: largest penetration left after a correction ', pen_max, ' m; edge particle: '// &
      'first contact ', t_edge_first, ' s, separation ', t_edge_sep, ' s (-1: never)'
    do k = 1, ndef
      block
        real(wp) :: ext(4)
        call body_extent(tbs(k), ext)
        write(output_unit, '(a,es12.5,a,es12.5,a,es12.5,a,f8.4)') 'summary: body '''// &
          trim(bodies(tbs(k)%ibody)%name)//''': length ', ext(1), ' m, width ', ext(2), &
          ' m, foot radius ', ext(3), ' m, max epsbar ', ext(4)
      end block
    end do
    write(output_unit, '(a,f8.2,a,6(a,f5.1,a))') 'summary: time loop ', t_loop, ' s: ', &
      'kinematics ', 100.0_wp*time_share(1), '%, ', 'material ', 100.0_wp*time_share(2), &
      '%, ', 'internal force ', 100.0_wp*time_share(3), '%, ', 'contact ', &
      100.0_wp*t_contact/max(t_loop, 1.0e-9_wp), '%, ', 'snapshots ', &
      100.0_wp*t_output/max(t_loop, 1.0e-9_wp), '%, ', 'rest ', 100.0_wp*(1.0_wp - &
      sum(time_share()) - (t_contact + t_output)/max(t_loop, 1.0e-9_wp)), '%'
    write(output_unit, '(a)') 'summary: wrote '//trim(deck%output%file)//' and '//xdmf
    if (failed .and. .not. allocated(err)) call set_error(err, 'run failed at '//reason// &
      '; diagnostic snapshot /snapshots/failure written', exit_run_failed)

  contains

    !> /snapshots/<label>/det/contact<k>: det(M_master), det(M_slave) on the deck's grid and
    !! det(M_master) at the slave particles.
    subroutine det_fields_out(lab)
      character(len=*), intent(in) :: lab
      real(wp), allocatable :: dm(:), ds(:), dms(:)
      integer :: kp, ng(2)
      character(len=:), allocatable :: g
      ng = deck%output%det_grid_n
      call h5_group(f, '/snapshots/'//lab//'/det', err)
      do kp = 1, size(pairs)
        if (allocated(err)) return
        allocate(dm(product(ng)), ds(product(ng)), dms(tbs(pairs(kp)%side(1)%itb)%np))
        call contact_det_fields(pairs(kp), tbs, bodies, deck%output%det_grid_lo, &
          deck%output%det_grid_hi, ng, dm, ds, dms, err)
        g = '/snapshots/'//lab//'/det/contact'//itoa(kp)
        if (.not. allocated(err)) call h5_group(f, g, err)
        if (.not. allocated(err)) call h5_write(f, g//'/master', reshape(dm, ng), '1', err, &
          'det(M) of the master on the grid (axis1 fastest)')
        if (.not. allocated(err)) call h5_write(f, g//'/slave', reshape(ds, ng), '1', err, &
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
    end subroutine det_fields_out

    function grid_axis(k) result(a)
      integer, intent(in) :: k
      real(wp), allocatable :: a(:)
      integer :: i, nk
      nk = deck%output%det_grid_n(k)
      allocate(a(nk))
      do i = 1, nk
        a(i) = deck%output%det_grid_lo(k) + (deck%output%det_grid_hi(k) - &
          deck%output%det_grid_lo(k))*real(i - 1, wp)/real(nk - 1, wp)
      end do
    end function grid_axis

    !> Contact corrections of every pair between the prediction and the forces.
    subroutine contact_step()
      integer :: kp
      logical :: edge_now
      do kp = 1, ndef
        tbs(kp)%fcon = 0.0_wp
      end do
      nc_step = 0
      fc_step = 0.0_wp
      rad_step = 0.0_wp
      pen_step = 0.0_wp
      edge_now = .false.
      do kp = 1, size(pairs)
        call contact_correct(pairs(kp), tbs, dt, err)
        if (allocated(err)) return
        nc_step = nc_step + pairs(kp)%step%n_contact
        fc_step = fc_step + pairs(kp)%step%force_normal
        rad_step = max(rad_step, pairs(kp)%step%radius)
        pen_step = max(pen_step, pairs(kp)%step%pen_after)
        edge_now = edge_now .or. pairs(kp)%step%edge_in_contact
      end do
      pen_max = max(pen_max, pen_step)
      impulse = impulse + fc_step*dt
      if (edge_now .and. t_edge_first < 0.0_wp) t_edge_first = t + dt
      if (edge_prev .and. .not. edge_now) t_edge_sep = t + dt
      edge_prev = edge_now
    end subroutine contact_step

    subroutine snapshots_due()
      character(len=8) :: lab
      do while (nsnap_done < deck%solver%nsnap)
        if (deck%solver%snapshot_times(nsnap_done + 1) > t + 0.5_wp*dt) exit
        nsnap_done = nsnap_done + 1
        write(lab, '(i4.4)') nsnap_done
        call snapshot_write(f, trim(lab), t, n, bodies, tbs, err)
        if (allocated(err)) return
        if (deck%output%det_fields) call det_fields_out(trim(lab))
        if (allocated(err)) return
        labels = [character(len=8) :: labels, lab]
        snap_t = [snap_t, t]
        call history_flush(f, hist, err)
        call xdmf_write(xdmf, basename(trim(deck%output%file)), labels, snap_t, bodies, tbs)
        write(output_unit, '(a,es12.5,a)') 'dynamic: snapshot '//trim(lab)//' at t = ', t, ' s'
      end do
    end subroutine snapshots_due

    function history_row() result(row)
      real(wp) :: row(size(history_names)), ext(4)
      call body_extent(tbs(1), ext)
      row = [real(n, wp), t, dt, en%ke, en%w_int, en%w_plastic, en%w_ext, en%w_contact, &
        en%residual, real(nc_step, wp), fc_step, rad_step, pen_step, ext(1), ext(3), impulse]
    end function history_row

    subroutine log_line()
      real(wp) :: eta
      twrite = omp_get_wtime() - wall0
      eta = 0.0_wp
      if (n > 0) eta = twrite/real(n, wp)*real(max(nsteps_est - n, 0), wp)
      write(output_unit, '(a,i9,es14.6,es11.3,6es13.4,i7,f9.1)') 'dynamic: ', n, t, dt, en%ke, &
        en%w_int, en%w_plastic, en%w_ext, en%w_contact, en%residual, nc_step, eta
    end subroutine log_line

    !> Shares of the time loop spent in kinematics, material update and internal force.
    function time_share(i) result(share)
      integer, intent(in), optional :: i
      real(wp), allocatable :: share(:)
      real(wp) :: tot(3)
      integer :: kk
      tot = 0.0_wp
      do kk = 1, ndef
        tot = tot + tbs(kk)%wall
      end do
      tot = tot/max(t_loop, 1.0e-9_wp)
      if (present(i)) then
        share = [tot(i)]
      else
        share = tot
      end if
    end function time_share

    function run_status() result(st)
      character(len=:), allocatable :: st
      if (failed) then
        st = 'failed'
      else if (t < deck%solver%t_end - 0.5_wp*dt) then
        st = 'stopped at max_steps'
      else
        st = 'completed'
      end if
    end function run_status

    subroutine write_summary()
      integer :: kk
      real(wp) :: ext(4)
      call h5_group(f, '/summary', err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'status', &
        trim(run_status()), err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'failure', reason, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'steps', n, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'time', t, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'dt', dt, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'dt_critical', dtc, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'wall_time', wall, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', &
        'time_loop_kinematics_material_force_contact_snapshots', [t_loop, time_share(), &
        t_contact, t_output], err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'threads', omp_get_max_threads(), &
        err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'particle_steps_per_second', &
        real(psteps, wp)/max(t_loop, 1.0e-9_wp), err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'energy_residual', en%residual, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'energy_scale', en%scale, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'kinetic_energy', en%ke, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'internal_work', en%w_int, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'plastic_dissipation', &
        en%w_plastic, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'contact_work', en%w_contact, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'max_remaining_penetration', &
        pen_max, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'edge_first_contact_time', &
        t_edge_first, err)
      if (.not. allocated(err)) call h5_attr(f, '/summary', 'edge_separation_time', &
        t_edge_sep, err)
      do kk = 1, size(pairs)
        if (.not. allocated(err)) call h5_attr(f, '/summary', 'contact'//itoa(kk)// &
          '_counts_screened_evaluated_detected_contacts', real([pairs(kk)%count%screened, &
          pairs(kk)%count%evaluated, pairs(kk)%count%detected, pairs(kk)%count%contacts], wp), &
          err)
      end do
      do kk = 1, ndef
        call body_extent(tbs(kk), ext)
        if (.not. allocated(err)) call h5_attr(f, '/summary', &
          trim(bodies(tbs(kk)%ibody)%name)//'_length_width_footradius_maxepsbar', ext, err)
      end do
    end subroutine write_summary
  end subroutine run_dynamic

  !> The prediction of eq. (64) for one body (contact corrects it afterwards).
  subroutine predict_body(tb, dt)
    type(tl_body_t), intent(inout) :: tb
    real(wp), intent(in) :: dt
    integer :: i
    !$omp parallel do default(none) shared(tb, dt) schedule(static)
    do i = 1, tb%np
      where (tb%pres(:, i))
        tb%v(:, i) = tb%vpres(:, i)
        tb%a(:, i) = 0.0_wp
      end where
      tb%d_old(:, i) = tb%d(:, i)
      tb%v_old(:, i) = tb%v(:, i)
      tb%d(:, i) = tb%d(:, i) + dt*tb%v(:, i) + 0.5_wp*dt*dt*tb%a(:, i)   ! (64)
      tb%a_old(:, i) = tb%a(:, i)
    end do
    !$omp end parallel do
  end subroutine predict_body

  !> Forces at the (corrected) new coefficients, eq. (62), and the velocity, eq. (63),
  !! with the work of kinematic conditions and of contact forces over the step (trapezoid
  !! 1/2 f . du, like the internal work; a contact force acts at n only) and the kinetic
  !! energy.
  subroutine finish_body(tb, dt, bad_q, bad_j)
    type(tl_body_t), intent(inout) :: tb
    real(wp), intent(in) :: dt
    integer, intent(out) :: bad_q
    real(wp), intent(out) :: bad_j
    integer :: i
    real(wp) :: wbc, wc, ke, du(2)
    ! a_n as corrected by contact (eq. 63 uses it)
    tb%a_old = tb%a
    call tl_body_forces(tb, dt, bad_q, bad_j)                       ! (62)
    wbc = 0.0_wp
    wc = 0.0_wp
    ke = 0.0_wp
    !$omp parallel do default(none) shared(tb, dt) private(du) reduction(+: wbc, wc, ke) &
    !$omp schedule(static)
    do i = 1, tb%np
      where (tb%pres(:, i))
        tb%v(:, i) = tb%vpres(:, i)
        tb%a(:, i) = 0.0_wp
      end where
      tb%v(:, i) = tb%v(:, i) + 0.5_wp*dt*(tb%a_old(:, i) + tb%a(:, i))   ! (63)
      where (tb%pres(:, i)) tb%v(:, i) = tb%vpres(:, i)
      ! kinematic conditions: reactions R = f_int - f_ext times the motion
      tb%freac(:, i) = merge(tb%fint(:, i) - tb%fext(:, i), 0.0_wp, tb%pres(:, i))
      du = tb%d(:, i) - tb%d_old(:, i)
      wbc = wbc + 0.5_wp*sum((tb%freac_old(:, i) + tb%freac(:, i))*du)
      tb%freac_old(:, i) = tb%freac(:, i)
      wc = wc + 0.5_wp*sum(tb%fcon(:, i)*du)
      ke = ke + 0.5_wp*tb%t%mass(i)*sum(tb%v(:, i)**2)
    end do
    !$omp end parallel do
    tb%w_bc = tb%w_bc + wbc
    tb%w_contact = tb%w_contact + wc
    tb%ke = ke
  end subroutine finish_body

  !> Length (extent in x2), width (extent in x1), foot radius (largest x1 within one
  !! spacing of the lowest x2) and the largest effective plastic strain of a body (m, m, m, 1).
  subroutine body_extent(tb, ext)
    type(tl_body_t), intent(inout) :: tb
    real(wp), intent(out) :: ext(4)
    real(wp) :: zmin
    call physical_positions(tb%t, tb%x0, tb%d, tb%x)
    zmin = minval(tb%x(2, :))
    ext(1) = maxval(tb%x(2, :)) - zmin
    ext(2) = maxval(tb%x(1, :)) - minval(tb%x(1, :))
    ext(3) = maxval(tb%x(1, :), mask=tb%x(2, :) <= zmin + tb%t%hmin)
    ext(4) = maxval(tb%st%epsbar)
  end subroutine body_extent

  !> 'fastest particle J of body B (|v| = ...)': where an instability usually grows.
  function fastest_particle(tbs, bodies) result(msg)
    type(tl_body_t), intent(in) :: tbs(:)
    type(body_t), intent(in) :: bodies(:)
    character(len=:), allocatable :: msg
    integer :: k, j, kb, jb
    real(wp) :: vmax, v
    vmax = -1.0_wp
    kb = 1
    jb = 1
    do k = 1, size(tbs)
      do j = 1, tbs(k)%np
        v = norm2(tbs(k)%v(:, j))
        if (v > vmax) then
          vmax = v
          kb = k
          jb = j
        end if
      end do
    end do
    msg = 'fastest particle '//itoa(jb)//' of body '''//trim(bodies(tbs(kb)%ibody)%name)// &
      ''' (|v| = '//rtoa(vmax)//' m/s)'
  end function fastest_particle

  pure integer function first_bad(tb) result(i)
    type(tl_body_t), intent(in) :: tb
    integer :: j
    i = 0
    do j = 1, tb%np
      if (.not. all(abs(tb%d(:, j)) < huge(1.0_wp) .and. abs(tb%v(:, j)) < huge(1.0_wp))) then
        i = j
        return
      end if
    end do
  end function first_bad

  subroutine energy_totals(tbs, en)
    type(tl_body_t), intent(in) :: tbs(:)
    type(energies_t), intent(inout) :: en
    integer :: k
    en%ke = 0.0_wp
    en%ke0 = 0.0_wp
    en%w_int = 0.0_wp
    en%w_plastic = 0.0_wp
    en%w_ext = 0.0_wp
    en%w_contact = 0.0_wp
    do k = 1, size(tbs)
      en%ke = en%ke + tbs(k)%ke
      en%ke0 = en%ke0 + tbs(k)%ke0
      en%w_int = en%w_int + tbs(k)%w_int + tbs(k)%e_stab
      en%w_plastic = en%w_plastic + tbs(k)%w_plastic
      en%w_ext = en%w_ext + tbs(k)%w_ext + tbs(k)%w_bc
      en%w_contact = en%w_contact + tbs(k)%w_contact
    end do
    en%residual = en%ke + en%w_int - en%ke0 - en%w_ext - en%w_contact
    en%scale = max(en%ke0, en%ke, abs(en%w_int), abs(en%w_ext), abs(en%w_contact), &
      tiny(1.0_wp))
  end subroutine energy_totals

  pure function basename(path) result(b)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: b
    b = path(index(path, '/', back=.true.) + 1:)
  end function basename
end module explicit_driver_m
