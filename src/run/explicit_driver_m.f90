!> The explicit central-difference driver of a dynamic run, eqs. (62)-(64):
!!   u_{n+1} = u_n + dt v_n + dt^2/2 a_n                      (64)
!!   a_{n+1} = M^-1 (f_ext - f_int(u_{n+1}))                  (62)
!!   v_{n+1} = v_n + dt/2 (a_n + a_{n+1})                     (63)
!! with the row-sum lumped mass (70), for solids of any discretization (RKPM particles or
!! CST4 elements), serial or on MPI ranks: one loop, whatever run_domain_t it is given (a
!! serial run is the one-rank case, whose parts are its solids and whose collectives change
!! nothing; on ranks each solid is the rank's part, which exchanges its ghosts with its
!! neighbours itself: solid_m's part_halo_t). Each step: the step size, predict (64),
!! contact (93)-(98), internal force (62) and update (63), energies and guards, output. A
!! run that goes unstable (non-finite values, J <= 0, energy residual above the deck's
!! tolerance) stops with a diagnostic snapshot and exit code 1, keeping everything written
!! so far. With &output checkpoint_every the state is saved every so many steps, and a run
!! restarted from such a checkpoint (set up from the same deck, on any number of ranks)
!! continues the loop where it was, taking the same steps (run_checkpoint_m).
module explicit_driver_m
  use omp_lib, only: omp_get_wtime
  use kinds_m, only: wp
  use dims_m, only: max_dim
  use exact_sum_m, only: exact_sum_t, exact_allsum_many
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use log_m, only: log_print
  use rank_comm_m, only: rank_comm_t
  use deck_m, only: deck_t
  use body_m, only: body_t
  use solid_m, only: solid_t, solid_start, solid_predict, solid_internal_force, &
    solid_update, solid_share_corrections, solid_body_sums, solid_bc_reactions, &
    solid_sums_size, solid_account_sums
  use contact_pair_m, only: contact_pair_t, contact_step, contact_stats_t
  use body_measures_m, only: measures_t
  use run_health_m, only: energies_t, energy_totals, energies_of, check_solid, check_energy, &
    check_step, set_health_limits
  use stable_step_m, only: step_control_next, step_control_update, landing_slack
  use subcycle_m, only: subcycle_next, subcycle_rates, subcycle_end
  use dynamic_setup_m, only: dynamic_setup_t, setup_time_step
  use dynamic_output_m, only: history_t, history_push, history_flush, history_width, &
    history_names, history_geometry, pair_columns, hist_axisym, hist_3d
  use run_report_m, only: run_record_t, record_contact, log_header, log_line, &
    history_row_measured, report_summary
  use run_files_m, only: run_files_t, run_files_open, snapshot_due, snapshot_others, &
    failure_snapshot, run_files_close, run_files_names, run_files_resume, snapshot_needs_state
  use run_checkpoint_m, only: checkpoint_read
  use run_domain_m, only: run_domain_t
  implicit none
  private
  public :: run_dynamic, next_stop, output_intervals

  !> Steps before the energy guard is armed (see check_energy).
  integer, parameter :: energy_warmup = 20
  !> The step estimate t_end/dt within this of a whole number is that number (the quotient
  !! of two decimal inputs carries a few ulps of error).
  real(wp), parameter :: count_slack = 1.0e-9_wp
  !> A stop time within this relative amount of t has been reached: steps land on stops to
  !! the rounding of a sum of steps (a few ulps of t).
  real(wp), parameter, public :: stop_passed = 1.0e-12_wp

contains

  !> Run the deck's dynamic problem on the ranks of dom (a serial_domain_t for one).
  !! bodies are built and checked already, su is their set-up (setup_dynamic; its solids
  !! and pairs are moved in). restart: a checkpoint of this deck's run to continue from
  !! (checked already by checkpoint_check; a checkpoint that does not fit the solids is
  !! still bad input, found before any write), written on any number of ranks.
  subroutine run_dynamic(deck, bodies, su, dom, err, restart)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(dynamic_setup_t), intent(inout) :: su
    class(run_domain_t), intent(inout), target :: dom
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: restart
    type(solid_t), allocatable, target :: solids(:)
    type(contact_pair_t), allocatable, target :: pairs(:)
    type(solid_t), pointer :: whole(:)
    integer, allocatable :: isolid(:)
    type(run_files_t) :: out
    type(run_record_t) :: r
    type(energies_t) :: en
    type(contact_stats_t) :: cstep
    type(history_t) :: hist0
    type(measures_t), allocatable :: bms(:)
    real(wp), allocatable :: snap_times0(:), row(:)
    integer :: k, k_bad, log_every, hist_every, bad_q, nsnap0, ckpt_every
    logical :: needs_state
    integer :: gathers0
    real(wp) :: tw, t_loop0, bad_j, phase(3)
    call run_take_setup(deck, su, solids, isolid, pairs, r, dom%comm)
    allocate(bms(size(solids)))
    if (present(restart)) then
      ! the record, the solids' scalars, the pairs' counters, the history; the state fields
      ! whole (serial) or each part its own rows in the split
      dom%restart_from = restart
      call checkpoint_read(restart, deck, bodies, r, solids, pairs, hist0, nsnap0, &
        snap_times0, err, fields=.not. dom%reads_parts)
      if (dom%any_error(err)) return
    end if
    call dom%split(solids, pairs, present(restart), su%trees, err)
    if (dom%any_error(err)) return
    ! the step from the power iteration on the parts (a restart's is the checkpoint's)
    if (.not. present(restart)) call run_first_step(deck, solids, r, dom)
    ckpt_every = deck%output%checkpoint_every
    call output_intervals(deck, r%nsteps_est, log_every, hist_every)
    allocate(row(history_width(size(solids), size(pairs), deck%nbcs, &
      history_geometry(solids(1)%t%dims%ndim, solids(1)%t%axisym))))
    if (dom%root) call run_files_open(deck, bodies, out, err, restart)
    if (dom%any_error(err)) return
    ! (on ranks the deformable bodies' rows from every rank's share, collectively)
    call dom%bodies_rows(out, bodies, err)
    if (dom%any_error(err)) return
    ! rank 0's whole solids (their sizes and tables; their state when gathered, here for
    ! det(M) fields at t = 0 only)
    needs_state = snapshot_needs_state(deck)
    whole => dom%whole(solids, .false., state=needs_state .and. .not. present(restart))
    if (present(restart)) then
      ! the state after step r%n, as the checkpoint holds it
      if (dom%root) call run_files_resume(out, restart, r, hist0, nsnap0, snap_times0, err)
      if (dom%any_error(err)) return
      ! (every rank counts the snapshots: their solids' datasets are written by all)
      out%nsnap_done = nsnap0
      call energies_exact(dom, solids, en)
    else
      ! the state at t = 0: forces at u = 0
      do k = 1, size(solids)
        call solid_start(solids(k), r%dt, bad_q, bad_j)
      end do
      call energies_exact(dom, solids, en)
      call snapshots_due(dom, out, deck, r, pairs, solids, whole, err)
      if (dom%any_error(err)) then
        if (dom%root) call run_files_close(out, r, whole, err)
        return
      end if
      call history_row_now(dom, solids, pairs, r, en, row)
      if (dom%root) call history_push(out%hist, row)
    end if
    if (dom%root) then
      call log_header()
      call log_line(r, en)
    end if
    t_loop0 = omp_get_wtime()
    gathers0 = dom%gathers
    do while (r%t < r%t_end - 0.5_wp*r%dt .and. r%n < deck%solver%max_steps)
      ! the step, and with &solver subcycle its sub-steps (subcycle_m; one rank only)
      if (r%n > 0) r%dt = subcycle_next(r%step, solids, r%t, next_stop(deck, r%t), &
        deck%solver%subcycle, r%sub)
      do k = 1, size(solids)
        call solid_predict(solids(k), r%dt)                                     ! (64)
      end do
      tw = omp_get_wtime()
      call contact_step(pairs, solids, r%dt, r%t + r%dt, cstep, err)           ! (93)-(98)
      if (dom%any_error(err)) exit
      call dom%contact_stats(cstep, pairs)
      do k = 1, size(solids)
        call solid_share_corrections(solids(k))
      end do
      r%t_contact = r%t_contact + (omp_get_wtime() - tw)
      ! (subcycling: the rates' own steps inside this one; k_bad > 0 if one of them broke)
      call subcycle_rates(pairs, solids, r%t, r%dt, cstep, r%sub, r%t_contact, k_bad, bad_q, &
        bad_j, err)
      ! (no collective here: subcycling runs on one rank only, mpi_scene_check)
      if (allocated(err)) exit
      call record_contact(r, cstep, r%t + r%dt)
      r%n = r%n + 1
      r%t = r%t + r%dt
      if (k_bad > 0) then
        call solid_checked(solids(k_bad), k_bad, r, bad_q, bad_j)
      else
        call internal_forces_and_update(dom, solids, r)                        ! (62), (63)
      end if
      call kappa_max(dom, solids)
      call subcycle_end(solids)
      call step_control_update(r%step, solids)
      if (.not. r%failed) call check_step(r%step, solids, r%n, r%failed, r%reason, r%fail_key)
      call energies(dom, solids, en)
      if (.not. r%failed) call check_energy(en, r%n, energy_warmup, deck%solver%energy_tol, &
        solids, r%energy_over, r%failed, r%reason, r%fail_key)
      ! a failure on any rank fails all, with the reason the serial run would give
      call dom%agree_failure(r)
      ! what the history, the log and the summary record: the exact accounts (the running
      ! ones, which the guard reads each step, depend on the split in their last bits)
      if (mod(r%n, hist_every) == 0 .or. mod(r%n, log_every) == 0 .or. r%failed) &
        call energies_exact(dom, solids, en)
      ! the whole solids' state for a snapshot that draws det(M) fields from it (on ranks,
      ! gathered to rank 0 then only: the solids' datasets are written from the parts, and
      ! a history row's measures are maxima over the ranks)
      if (snapshot_near(deck, r) .and. needs_state) whole => dom%whole(solids, .false.)
      if (mod(r%n, hist_every) == 0 .or. r%failed) then
        call history_row_now(dom, solids, pairs, r, en, row)
        if (dom%root) call history_push(out%hist, row)
      end if
      if (dom%root .and. (mod(r%n, log_every) == 0 .or. r%failed)) call log_line(r, en)
      if (r%failed) exit
      tw = omp_get_wtime()
      call snapshots_due(dom, out, deck, r, pairs, solids, whole, err)
      if (dom%any_error(err)) exit
      if (ckpt_every > 0) then
        if (mod(r%n, ckpt_every) == 0) call dom%checkpoint(out, bodies, r, solids, &
          pairs, r%t_loop + (omp_get_wtime() - t_loop0), err)
      end if
      r%t_output = r%t_output + (omp_get_wtime() - tw)
      if (dom%any_error(err)) exit
    end do
    ! a restarted run adds the loop time of the runs before it (from the checkpoint)
    r%t_loop = r%t_loop + (omp_get_wtime() - t_loop0)
    if (dom%root .and. dom%comm%nranks > 1) call log_print('dynamic: the state gathered '// &
      'to rank 0 '//itoa(dom%gathers - gathers0)//' time(s) in the time loop (det(M) '// &
      'fields of snapshots)')
    call energies_exact(dom, solids, en)
    ! (the last row before the counters are summed over the ranks: its friction work sums
    ! each rank's own)
    if (.not. r%failed .and. mod(r%n, hist_every) /= 0) &
      call history_row_now(dom, solids, pairs, r, en, row)
    call dom%counters(pairs, .false.)
    call dom%finish(solids, pairs, r)
    ! the bodies' measures for the summary (on ranks from the parts, collectively)
    do k = 1, size(solids)
      bms(k) = dom%measures(solids(k))
    end do
    ! the summary's shares of the time loop in kinematics, material and internal force:
    ! each part's wall times, their mean over the ranks, added on rank 0 to its whole
    ! solids' (shells without them but for what a restart's checkpoint held: the summary
    ! said 0% of each on ranks); a serial run's solids are its whole ones
    do k = 1, size(solids)
      phase = solids(k)%acc%wall
      call dom%comm%sum_real(phase)
      if (dom%root .and. .not. associated(whole, solids)) &
        whole(k)%acc%wall = whole(k)%acc%wall + phase/real(dom%comm%nranks, wp)
    end do
    ! a failed run's diagnostic snapshot: its solids' datasets (on ranks from the parts)
    if (r%failed) then
      if (dom%root) call log_print('dynamic: FAILED at '//r%reason)
      call dom%snapshot_solids(out, 'failure', r, solids, err)
      ! (every rank learns of a rank's write error: rank 0 then writes no more)
      call dom%agree_error(err)
    end if
    if (dom%root) then
      if (r%failed) then
        if (.not. allocated(err)) call failure_snapshot(out, r, whole, err)
      else if (mod(r%n, hist_every) /= 0) then
        call history_push(out%hist, row)
      end if
      if (.not. allocated(err)) call history_flush(out%f, out%hist, err)
      if (.not. allocated(err)) call report_summary(out%f, r, en, pairs, whole, bms, &
        run_files_names(out, r%failed), err)
      call run_files_close(out, r, whole, err)
    end if
    if (dom%any_error(err)) return
    if (r%failed .and. .not. allocated(err)) call set_error(err, 'run failed: '// &
      r%reason, 1)
  end subroutine run_dynamic

  !> The deck's snapshots due by the record's time: the solids' datasets (on ranks each
  !! writes its part's rows, collectively), then on rank 0 the rest (snapshot_others, the
  !! det(M) fields from the whole solids, gathered when they are needed).
  subroutine snapshots_due(dom, out, deck, r, pairs, solids, whole, err)
    class(run_domain_t), intent(inout), target :: dom
    type(run_files_t), intent(inout) :: out
    type(deck_t), intent(in) :: deck
    type(run_record_t), intent(in) :: r
    type(contact_pair_t), intent(inout), target :: pairs(:)
    type(solid_t), intent(inout) :: solids(:)
    type(solid_t), pointer, intent(in) :: whole(:)   !< (serial: solids themselves)
    type(error_t), allocatable, intent(inout) :: err
    character(len=8) :: lab
    do
      lab = snapshot_due(out, deck, r)
      if (lab == '') exit
      call dom%snapshot_solids(out, trim(lab), r, solids, err, pairs)
      if (dom%root .and. .not. allocated(err)) call snapshot_others(out, deck, trim(lab), &
        r, dom%output_pairs(pairs), whole, err)
      if (dom%any_error(err)) exit
    end do
  end subroutine snapshots_due

  !> The set-up's solids, body-to-solid map and pairs moved out of su, the health limits
  !! set (over the ranks of comm), and the run record started.
  subroutine run_take_setup(deck, su, solids, isolid, pairs, r, comm)
    type(deck_t), intent(in) :: deck
    type(dynamic_setup_t), intent(inout) :: su
    type(solid_t), allocatable, intent(out) :: solids(:)
    integer, allocatable, intent(out) :: isolid(:)
    type(contact_pair_t), allocatable, intent(out) :: pairs(:)
    type(run_record_t), intent(inout) :: r
    class(rank_comm_t), intent(inout) :: comm
    r%wall0 = su%wall0
    r%reason = ''
    call move_alloc(su%solids, solids)
    call move_alloc(su%isolid, isolid)
    call move_alloc(su%pairs, pairs)
    call set_health_limits(solids, comm)
    r%t_end = deck%solver%t_end
  end subroutine run_take_setup

  !> The step control calibrated on the parts (collective), the first step and the step
  !! estimate.
  subroutine run_first_step(deck, solids, r, dom)
    type(deck_t), intent(in) :: deck
    type(solid_t), intent(inout) :: solids(:)
    type(run_record_t), intent(inout) :: r
    class(run_domain_t), intent(inout) :: dom
    call setup_time_step(deck, solids, r%step, dom%comm)
    r%dt = step_control_next(r%step, 0.0_wp, next_stop(deck, 0.0_wp))
    r%nsteps_est = ceiling(r%t_end/r%dt - count_slack)
  end subroutine run_first_step

  !> Steps between log lines and between history rows: the deck's, or by default about 50
  !! log lines a run and a history row every 10 steps (a row costs about one pass over the
  !! nodes, for the measures), at most about 1000 rows and never fewer than log lines.
  pure subroutine output_intervals(deck, nsteps_est, log_every, hist_every)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: nsteps_est
    integer, intent(out) :: log_every, hist_every
    log_every = deck%solver%log_every
    if (log_every == 0) log_every = max(1, nsteps_est/50)
    hist_every = deck%solver%history_every
    if (hist_every == 0) hist_every = max(1, min(log_every, max(10, nsteps_est/1000)))
  end subroutine output_intervals

  !> The next time the run must land on after t: the next snapshot time, else t_end.
  pure real(wp) function next_stop(deck, t) result(ts)
    type(deck_t), intent(in) :: deck
    real(wp), intent(in) :: t
    integer :: k
    ts = deck%solver%t_end
    do k = 1, deck%solver%nsnap
      if (deck%solver%snapshot_times(k) > t*(1.0_wp + stop_passed) .and. &
        deck%solver%snapshot_times(k) < ts) ts = deck%solver%snapshot_times(k)
    end do
  end function next_stop

  !> Internal forces at the corrected prediction (62), the velocities (63), and the guards
  !! on J, stresses and non-finite values, for every solid (on ranks each part exchanges
  !! its ghosts inside solid_internal_force and solid_update).
  subroutine internal_forces_and_update(dom, solids, r)
    class(run_domain_t), intent(in) :: dom
    type(solid_t), intent(inout) :: solids(:)
    type(run_record_t), intent(inout) :: r
    integer :: k, bad_q
    real(wp) :: bad_j
    do k = 1, size(solids)
      call solid_internal_force(solids(k), r%dt, bad_q, bad_j)                 ! (62)
      call solid_update(solids(k), r%dt)                                        ! (63)
      call solid_checked(solids(k), k, r, bad_q, bad_j)
      r%node_steps = r%node_steps + dom%whole_nodes(solids, k)
      r%point_steps = r%point_steps + dom%whole_points(solids, k)
    end do
  end subroutine internal_forces_and_update

  !> The energy accounts of the solids, summed over the ranks (each part sums its own
  !! entries), with the residual and scale of the sums.
  subroutine energies(dom, solids, en)
    class(run_domain_t), intent(inout) :: dom
    type(solid_t), intent(in) :: solids(:)
    type(energies_t), intent(out) :: en
    real(wp) :: v(6)
    call energy_totals(solids, en)
    if (dom%comm%nranks == 1) return
    v = [en%ke, en%ke0, en%w_int, en%w_plastic, en%w_ext, en%w_contact]
    call dom%comm%sum_real(v)
    en%ke = v(1)
    en%ke0 = v(2)
    en%w_int = v(3)
    en%w_plastic = v(4)
    en%w_ext = v(5)
    en%w_contact = v(6)
    en%residual = en%ke + en%w_int - en%ke0 - en%w_ext - en%w_contact
    en%scale = max(en%ke0, en%ke, abs(en%w_int), abs(en%w_ext), abs(en%w_contact), &
      tiny(1.0_wp))
  end subroutine energies

  !> check_solid of solid k (the k-th), its failure's key (run_health_m) in the record.
  subroutine solid_checked(s, k, r, bad_q, bad_j)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: k, bad_q
    type(run_record_t), intent(inout) :: r
    real(wp), intent(in) :: bad_j
    if (r%failed) return
    call check_solid(s, r%n, bad_q, bad_j, r%failed, r%reason, r%fail_key)
    if (r%failed) r%fail_key(1) = real(k, wp)
  end subroutine solid_checked

  !> The energy accounts the run records (history rows, log lines, the summary): each
  !! solid's exact sums over its entries (solid_account_sums) and over the ranks' parts,
  !! rounded once, then added solid by solid (energies_of): the same bits on any number of
  !! ranks and threads. Collective.
  subroutine energies_exact(dom, solids, en)
    class(run_domain_t), intent(inout) :: dom
    type(solid_t), intent(in) :: solids(:)
    type(energies_t), intent(out) :: en
    type(exact_sum_t) :: xs(8*size(solids))
    integer :: k
    do k = 1, size(solids)
      call solid_account_sums(solids(k), xs(8*k - 7:8*k))
    end do
    en = energies_of(reshape(exact_allsum_many(xs, dom%comm), [8, size(solids)]))
  end subroutine energies_exact

  !> The history row of the step (collective): the run's columns (history_row_measured,
  !! with the measures of the first solid) and, for each solid, its kinetic energy and
  !! momentum, and in plane strain its angular momentum about its centre of mass,
  !! L_o - x_c x P with L_o about the origin and x_c = sum M x / M (sums over the ranks'
  !! parts).
  subroutine history_row_now(dom, solids, pairs, r, en, row)
    class(run_domain_t), intent(inout) :: dom
    type(solid_t), intent(inout) :: solids(:)
    type(contact_pair_t), intent(in) :: pairs(:)
    type(run_record_t), intent(in) :: r
    type(energies_t), intent(in) :: en
    real(wp), intent(inout) :: row(:)
    type(measures_t) :: hm, bm
    integer :: k, nd, nv, c, o, geo, npc
    ! per solid (solid_body_sums): ke, M, P(nd), sum M x (nd), L_o (1 or 3)
    real(wp) :: v(solid_sums_size(size(solids(1)%state%d, 1))*size(solids)), xc(max_dim)
    type(exact_sum_t) :: vs(size(v))
    type(exact_sum_t) :: rs(size(row))
    real(wp) :: wf(size(pairs)), lcm(3), p(3)
    hm = dom%measures(solids(1))
    row(1:size(history_names)) = history_row_measured(r, en, hm)
    nd = size(solids(1)%state%d, 1)
    nv = solid_sums_size(nd)
    geo = history_geometry(nd, solids(1)%t%axisym)
    ! (exact sums over the ranks' parts: the serial values to the bit)
    do k = 1, size(solids)
      call solid_body_sums(solids(k), vs((k - 1)*nv + 1:k*nv))
    end do
    v = exact_allsum_many(vs, dom%comm)
    c = size(history_names)
    do k = 1, size(solids)
      o = (k - 1)*nv
      ! the body's measures (the first solid's are the run's: hm; collective on ranks)
      if (k > 1) bm = dom%measures(solids(k))
      if (k == 1) bm = hm
      xc(:nd) = v(o + 3 + nd:o + 2 + 2*nd)/max(v(o + 2), tiny(1.0_wp))
      select case (geo)
      case (hist_axisym)
        ! the kinetic energy and the momentum along the axis (x2); the Taylor measures
        row(c + 1:c + 6) = [v(o + 1), v(o + 2 + nd), bm%length, bm%width, bm%foot_radius, &
          bm%max_epsbar]
        c = c + 6
      case (hist_3d)
        ! L_cm = L_o - x_c x P, x_c = sum M x / M
        p = v(o + 3:o + 5)
        lcm = v(o + 9:o + 11) - [xc(2)*p(3) - xc(3)*p(2), xc(3)*p(1) - xc(1)*p(3), &
          xc(1)*p(2) - xc(2)*p(1)]
        row(c + 1:c + 11) = [v(o + 1), p, lcm, bm%extent(1:3), bm%max_epsbar]
        c = c + 11
      case default
        ! the plane kernel (dims_plane): L_cm = L_o - x_c x P, x_c = sum M x / M
        row(c + 1) = v(o + 1)
        row(c + 2:c + 1 + nd) = v(o + 3:o + 2 + nd)
        row(c + 2 + nd) = v(o + nv) - (xc(1)*v(o + 4) - xc(2)*v(o + 3))
        row(c + 3 + nd:c + 5 + nd) = [bm%width, bm%length, bm%max_epsbar]
        c = c + 5 + nd
      end select
    end do
    ! each pair's forces of the step (on ranks summed by dom%contact_stats) and friction
    ! work so far (each rank's own particles', summed here)
    o = c
    npc = pair_columns(geo)
    do k = 1, size(pairs)
      row(c + 1:c + npc) = [pairs(k)%step%force_normal, pairs(k)%step%force_tangential, &
        pairs(k)%step%force_slave(1:npc - 3), pairs(k)%count%w_friction]
      c = c + npc
    end do
    if (size(pairs) > 0) then
      ! (exact sums of the particles' terms over the ranks: the serial value to the bit)
      wf = exact_allsum_many([(pairs(k)%count%w_friction_sum, k = 1, size(pairs))], dom%comm)
      do k = 1, size(pairs)
        row(o + npc*k) = wf(k)
      end do
    end if
    ! each &bc group's reaction force, summed over the solids (and the ranks), exactly
    if (c < size(row)) then
      rs = exact_sum_t()
      do k = 1, size(solids)
        call solid_bc_reactions(solids(k), rs(:size(row) - c))
      end do
      row(c + 1:) = exact_allsum_many(rs(:size(row) - c), dom%comm)
    end if
  end subroutine history_row_now

  !> Every solid's largest kappa over the ranks (the same step everywhere) and where it is
  !! (kappa_g: the point the summary names).  Collective.
  subroutine kappa_max(dom, solids)
    class(run_domain_t), intent(inout) :: dom
    type(solid_t), intent(inout) :: solids(:)
    real(wp) :: v(1), own
    integer :: k, g(1)
    do k = 1, size(solids)
      associate (s => solids(k))
        if (.not. (s%part%on .and. allocated(s%part%qglob))) then
          s%kappa_g = s%kappa_q
          cycle
        end if
        ! (a part without owned points has no kappa of its own this step)
        g = huge(1)
        if (s%kappa_q > 0 .and. size(s%part%own_q) > 0) g = s%part%qglob(s%kappa_q)
        if (dom%comm%nranks == 1) then
          s%kappa_g = g(1)
          cycle
        end if
        own = merge(s%kappa, -1.0_wp, size(s%part%own_q) > 0)
        v = own
        call dom%comm%max_real(v)
        s%kappa = v(1)
        ! where it is: among the ranks with the largest, the lowest point number (serial)
        if (own /= v(1)) g = huge(1)
        call dom%comm%min_int(g)
        s%kappa_g = g(1)
      end associate
    end do
  end subroutine kappa_max

  !> Is a snapshot time within this step's reach (then the whole solids are needed)?
  pure logical function snapshot_near(deck, r)
    type(deck_t), intent(in) :: deck
    type(run_record_t), intent(in) :: r
    integer :: j
    snapshot_near = .false.
    do j = 1, deck%solver%nsnap
      if (abs(deck%solver%snapshot_times(j) - r%t) <= 0.5_wp*r%dt*(1.0_wp + landing_slack)) &
        snapshot_near = .true.
    end do
  end function snapshot_near
end module explicit_driver_m
