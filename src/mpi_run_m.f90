!> A dynamic run on MPI ranks (issue 12; doc/parallel.md): the explicit driver of eqs.
!! (62)-(64) on each rank's part of every solid, with the halo exchanges between the passes,
!! global sums and maxima, and the output gathered to rank 0, which writes the one HDF5 file
!! (and XDMF) a serial run writes.
!!
!! Every rank builds the whole set-up (bodies, solids, contact pairs: as a serial run), then
!! keeps its part of each solid (decomposition_m: recursive coordinate bisection of the
!! reference configuration) and narrows each contact pair to it. A step: predict every local
!! node (eq. 64); contact on the owned slave nodes (93)-(98); the ghost nodes' corrected d
!! and a from their owners; P at the owned points, the ghost points' P from theirs, the
!! force and a at the owned nodes (62); v at the owned nodes (63); the ghost nodes' v and a.
!! Nodal values are the serial ones to the bit for any number of ranks (doc/parallel.md);
!! energies and the contact force are sums of per-rank sums (round-off); kappa, and with it
!! the step, is a maximum (exact).
!!
!! The driver takes element meshes and RKPM bodies against rigid masters (each rank holds
!! the master whole) and deforming masters (each rank its own and ghost master particles:
!! contact_dist_sm; self-contact too), without subcycling; the deck is refused otherwise.
!! Rank 0 draws the snapshots' det(M) fields from the gathered state with its copy of the
!! pairs as set up. An RKPM side's contact forces are spread over RK neighbours (eq. 98): the
!! ghost particles' forces are exchanged before the spreading and the corrected ghost nodes
!! after (contact_exchange). Checkpoints are the serial ones, written by rank 0 from the
!! gathered state and read whole by every rank, so a run continues on any number of ranks.
module mpi_run_m
  use mpi_f08
  use omp_lib, only: omp_get_wtime
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use deck_m, only: deck_t
  use body_m, only: body_t
  use solid_m, only: solid_t, solid_init, solid_predict, solid_update, solid_set_owned, &
    solid_points_force, solid_nodes_force
  use decomposition_m, only: rcb_tree_t, rcb_build, rcb_part, local_part_t, local_part_build
  use halo_m, only: halo_plan_t, halo_plan_build, halo_nodes, halo_points
  use rank_comm_m, only: rank_comm_t
  use mpi_comm_m, only: mpi_ranks_t, mpi_ranks_init
  use contact_pair_m, only: contact_pair_t, contact_step, contact_stats_t, &
    contact_pair_localize, contact_pair_distribute, contact_dist_report, exchange_forces, &
    exchange_state
  use contact_m, only: contact_counters_t
  use run_health_m, only: energies_t, energy_totals, check_solid, check_energy, check_step
  use stable_step_m, only: step_control_next, step_control_update, landing_slack
  use dynamic_setup_m, only: dynamic_setup_t
  use explicit_driver_m, only: next_stop, output_intervals, run_take_setup
  use dynamic_output_m, only: history_t, history_push, history_flush
  use run_report_m, only: run_record_t, record_contact, log_header, log_line, history_row, &
    history_row_measured, report_summary
  use body_measures_m, only: measures_t, body_measures_part
  use run_files_m, only: run_files_t, run_files_open, snapshots_due, failure_snapshot, &
    run_files_close, run_files_names, run_files_resume, run_files_checkpoint
  use run_checkpoint_m, only: checkpoint_read
  implicit none
  private
  public :: run_dynamic_mpi, mpi_scene_check

  integer, parameter :: energy_warmup = 20

  !> A rank's part of one solid.
  type :: part_t
    type(local_part_t) :: lp
    type(halo_plan_t) :: plan
    real(wp), allocatable :: w(:, :)   !< (4, local nodes) work space for the halos
    integer, allocatable :: owner(:)   !< the rank (from 0) of each node of the whole solid
  end type part_t

  !> The parts of the run (module data: contact's exchanges reach their plans by index).
  type(part_t), allocatable, save :: parts(:)

  !> The default margin of the ghost width of contact with a deforming master, a fraction of
  !! the width contact needs: larger, fewer refreshes and more ghosts (doc/parallel.md)
  real(wp), parameter, public :: ghost_margin_default = 0.5_wp

contains

  !> What this driver cannot run yet, as bad input (before anything is written).
  subroutine mpi_scene_check(deck, err)
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    character(len=*), parameter :: what = "deck '"
    if (deck%run%mode /= 'dynamic') then
      call set_error(err, what//deck%path//"', group &run, variable mode: the MPI driver "// &
        "runs mode = 'dynamic' only; run mfcd for the others")
      return
    end if
    if (deck%solver%subcycle) then
      call set_error(err, what//deck%path//"', group &solver, variable subcycle: not yet "// &
        "with MPI; set subcycle = .false. or run mfcd")
      return
    end if
    do k = 1, deck%ncontacts
      associate (c => deck%contacts(k))
        if (deck%bodies(c%imaster)%role == 'rigid') cycle
        ! a deforming master (or self-contact): its ghost particles (contact_dist_sm)
        if (c%detector /= 'det_m' .or. c%compare_detectors) then
          call set_error(err, what//deck%path//"', group &contact, variable detector: "// &
            "against the deforming master '"//trim(c%master)//"' the MPI driver takes "// &
            "detector = 'det_m' (and compare_detectors = .false.); run mfcd for the others")
          return
        end if
        if (c%shared_mass) then
          call set_error(err, what//deck%path//"', group &contact, variable shared_mass: "// &
            "not yet with MPI; give .false. or run mfcd")
          return
        end if
      end associate
    end do
  end subroutine mpi_scene_check

  !> The run of deck on the ranks of comm (su: the set-up, the same on every rank).
  !! ghost_margin: the margin of the ghost width of contact with a deforming master, a
  !! fraction of the width contact needs; ghost_refresh .false.: testing only, the first
  !! ghost sets are kept (contacts they miss are missed).
  subroutine run_dynamic_mpi(comm, deck, bodies, su, ghost_margin, ghost_refresh, err, &
    restart)
    type(MPI_Comm), intent(in) :: comm
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(dynamic_setup_t), intent(inout) :: su
    real(wp), intent(in) :: ghost_margin
    logical, intent(in) :: ghost_refresh
    type(error_t), allocatable, intent(inout) :: err
    !> a checkpoint of this deck's run to continue from (checked by checkpoint_check), written
    !! by mfcd or mfcd_mpi on any number of ranks
    character(len=*), intent(in), optional :: restart
    type(history_t) :: hist0
    real(wp), allocatable :: snap_times0(:)
    integer :: nsnap0, ckpt_every
    type(mpi_ranks_t), target :: ranks
    type(solid_t), allocatable :: gs(:), ps(:)
    type(contact_pair_t), allocatable :: pairs(:)
    integer, allocatable :: isolid(:)
    type(run_files_t) :: out
    type(run_record_t) :: r
    type(energies_t) :: en
    type(contact_stats_t) :: cstep
    integer :: me, nranks, k, j, log_every, hist_every, bad_q, nsnap_before
    real(wp) :: t_loop0, bad_j, tw
    logical :: root
    class(rank_comm_t), pointer :: comm_ptr
    integer(i64), allocatable :: flag_max(:)
    type(contact_pair_t), allocatable :: pairs_whole(:)
    type(measures_t) :: hm
    call MPI_Comm_rank(comm, me)
    call MPI_Comm_size(comm, nranks)
    root = me == 0
    call run_take_setup(deck, su, gs, isolid, pairs, r)
    if (present(restart)) then
      ! every rank reads the whole state; rank 0 keeps the pairs' counters (sums)
      call checkpoint_read(restart, deck, bodies, r, gs, pairs, hist0, nsnap0, &
        snap_times0, err)
      if (any_error(comm, err)) return
    end if
    allocate(flag_max(size(pairs)))
    flag_max = [(pairs(k)%count%detected_max, k = 1, size(pairs))]
    if (.not. root) then
      do k = 1, size(pairs)
        pairs(k)%count = contact_counters_t()
      end do
    end if
    ! each solid's part, its halo plan and its part solid
    allocate(ps(size(gs)), parts(size(gs)))
    do k = 1, size(gs)
      call make_part(k)
      if (any_error(comm, err)) return
      if (present(restart)) call restart_part(k)
    end do
    ! rank 0's copy of the pairs as set up on the whole bodies, for the det(M) output of
    ! the snapshots (drawn from the gathered state: contact_det_fields, contact_self_det)
    if (root) allocate(pairs_whole, source=pairs)
    call mpi_ranks_init(ranks, comm)
    comm_ptr => ranks
    do k = 1, size(pairs)
      associate (s1 => pairs(k)%side(1)%isolid, s2 => pairs(k)%side(2)%isolid)
        if (s2 == 0) then
          call contact_pair_localize(pairs(k), parts(s1)%lp%nglob, ps, err)
        else
          ! a deforming master: each rank its own slave particles against its own and
          ! ghost master particles, and the other way round (contact_dist_sm)
          call contact_pair_distribute(pairs(k), ps, comm_ptr, parts(s1)%owner, &
            parts(s2)%owner, parts(s1)%lp%nglob, parts(s2)%lp%nglob, ghost_margin, &
            ghost_refresh, err)
        end if
      end associate
      if (any_error(comm, err)) return
      ! an RKPM side's contact forces are spread over RK neighbours (eq. 98): the ghost
      ! particles' forces before, the corrected ghost nodes after
      do j = 1, 2
        associate (s => pairs(k)%side(j))
          if (s%isolid == 0) cycle
          if (ps(s%isolid)%t%interpolating) cycle
          s%exchange => contact_exchange
          s%exchange_id = s%isolid
        end associate
      end do
    end do
    call output_intervals(deck, r%nsteps_est, log_every, hist_every)
    ckpt_every = deck%output%checkpoint_every
    if (present(restart)) then
      ! the state after step r%n, as the checkpoint holds it
      if (root) call run_files_open(deck, bodies, out, err, restart)
      if (root .and. .not. allocated(err)) call run_files_resume(out, restart, r, hist0, &
        nsnap0, snap_times0, err)
      if (any_error(comm, err)) return
      call global_energies()
      if (root) then
        call log_header()
        call log_line(r, en)
      end if
    else
      if (root) call run_files_open(deck, bodies, out, err)
      if (any_error(comm, err)) return
      call run_start()
      if (any_error(comm, err)) return
    end if
    t_loop0 = omp_get_wtime()
    do while (r%t < r%t_end - 0.5_wp*r%dt .and. r%n < deck%solver%max_steps)
      if (r%n > 0) r%dt = step_control_next(r%step, r%t, next_stop(deck, r%t))
      do k = 1, size(ps)
        call solid_predict(ps(k), r%dt)                                         ! (64)
      end do
      tw = omp_get_wtime()
      call contact_step(pairs, ps, r%dt, cstep, err)                            ! (93)-(98)
      if (any_error(comm, err)) exit
      call global_contact_stats(cstep)
      call global_flagged()
      do k = 1, size(ps)
        call halo_da(k)
      end do
      r%t_contact = r%t_contact + (omp_get_wtime() - tw)
      call record_contact(r, cstep, r%t + r%dt)
      r%n = r%n + 1
      r%t = r%t + r%dt
      do k = 1, size(ps)
        call solid_points_force(ps(k), r%dt, bad_q, bad_j)                      ! (62)
        call halo_pstab(k)
        call solid_nodes_force(ps(k))
        call solid_update(ps(k), r%dt)                                          ! (63)
        call halo_va(k)
        call check_solid(ps(k), r%n, bad_q, bad_j, r%failed, r%reason)
        r%node_steps = r%node_steps + gs(k)%np
        r%point_steps = r%point_steps + gs(k)%nq
      end do
      call agree_failure()
      call global_kappa()
      call step_control_update(r%step, ps)
      call check_step(r%step, ps, r%n, r%failed, r%reason)
      call global_energies()
      call check_energy(en, r%n, energy_warmup, deck%solver%energy_tol, ps, r%energy_over, &
        r%failed, r%reason)
      ! rank 0 gathers the state for a snapshot or a failure only; a history row's measures
      ! are maxima over the ranks
      if (r%failed .or. snapshot_near()) call gather_all()
      if (mod(r%n, hist_every) == 0 .or. r%failed) hm = body_measures_part(ps(1), ranks)
      if (root) then
        if (mod(r%n, hist_every) == 0 .or. r%failed) &
          call history_push(out%hist, history_row_measured(r, en, hm))
        if (mod(r%n, log_every) == 0 .or. r%failed) call log_line(r, en)
      end if
      if (r%failed) exit
      tw = omp_get_wtime()
      nsnap_before = 0
      if (root) then
        nsnap_before = out%nsnap_done
        call snapshots_due(out, deck, r, pairs_whole, gs, err)
      end if
      call reset_impulses_if_written(nsnap_before)
      if (any_error(comm, err)) exit
      if (ckpt_every > 0) then
        if (mod(r%n, ckpt_every) == 0) call write_checkpoint()
      end if
      r%t_output = r%t_output + (omp_get_wtime() - tw)
      if (any_error(comm, err)) exit
    end do
    r%t_loop = r%t_loop + (omp_get_wtime() - t_loop0)
    call gather_all()
    call global_counters()
    call halo_report()
    if (root) then
      if (r%failed) then
        call failure_snapshot(out, r, gs, err)
      else if (mod(r%n, hist_every) /= 0) then
        call history_push(out%hist, history_row(r, en, gs(1)))
      end if
      if (.not. allocated(err)) call history_flush(out%f, out%hist, err)
      if (.not. allocated(err)) call report_summary(out%f, r, en, pairs, gs, &
        run_files_names(out, r%failed), err)
      call run_files_close(out, r, gs, err)
    end if
    if (any_error(comm, err)) return
    if (r%failed .and. .not. allocated(err)) call set_error(err, 'run failed: '//r%reason)

  contains

    subroutine make_part(k)
      integer, intent(in) :: k
      type(rcb_tree_t) :: tree
      integer, allocatable :: node_part(:), point_part(:)
      integer :: i, q, kb, j
      associate (g => gs(k))
        call rcb_build(g%x0, nranks, tree)
        allocate(node_part(g%np), point_part(g%nq))
        do i = 1, g%np
          node_part(i) = rcb_part(tree, g%x0(:, i))
        end do
        do q = 1, g%nq
          point_part(q) = rcb_part(tree, g%t%xq(:, q))
        end do
        call local_part_build(g%t, node_part, point_part, me + 1, parts(k)%lp)
        parts(k)%owner = node_part - 1
        call halo_plan_build(comm, parts(k)%lp, node_part, point_part, parts(k)%plan, err)
        if (allocated(err)) return
        kb = findloc(isolid, k, dim=1)
        associate (lp => parts(k)%lp, n => parts(k)%lp%nglob)
          call solid_init(ps(k), g%name, lp%t, g%x0(:, n), &
            deck%materials(deck%bodies(kb)%imat)%params, 0.0_wp, [0.0_wp, 0.0_wp], &
            g%pres(:, n), g%vpres(:, n), err)
          if (allocated(err)) return
          call solid_set_owned(ps(k), lp%own_point, lp%own_node)
          ! RKPM's SCNI stabilization as the whole solid's (elements have none)
          ps(k)%stab_normal = g%stab_normal
          ps(k)%stab_shear = g%stab_shear
          ps(k)%v = g%v(:, n)
          ps(k)%ke0 = 0.0_wp
          do j = 1, size(ps(k)%own_n)
            i = ps(k)%own_n(j)
            ps(k)%ke0 = ps(k)%ke0 + 0.5_wp*ps(k)%t%mass(i)*sum(ps(k)%v(:, i)**2)
          end do
          ps(k)%ke = ps(k)%ke0
          ps(k)%spacing = g%spacing
          ps(k)%dt_cal = g%dt_cal
          ps(k)%v_limit = g%v_limit
          ps(k)%epsbar_limit = g%epsbar_limit
          ps(k)%deps_limit = g%deps_limit
          ps(k)%j_bounds = g%j_bounds
          allocate(parts(k)%w(4, ps(k)%np))
        end associate
      end associate
    end subroutine make_part

    !> The ghost points' P, and SCNI stabilization stresses, from their owners.
    subroutine halo_pstab(k)
      integer, intent(in) :: k
      call halo_points(parts(k)%plan, ps(k)%p)
      if (ps(k)%stab_normal > 0.0_wp) call halo_points(parts(k)%plan, ps(k)%stab)
    end subroutine halo_pstab

    !> The ghost nodes' d and a (after contact corrected them) from their owners.
    subroutine halo_da(k)
      integer, intent(in) :: k
      call halo_two(k, ps(k)%d, ps(k)%a)
    end subroutine halo_da

    !> The ghost nodes' v and a (after the update) from their owners.
    subroutine halo_va(k)
      integer, intent(in) :: k
      call halo_two(k, ps(k)%v, ps(k)%a)
    end subroutine halo_va

    !> Energy accounts summed over the ranks (each part sums its own entries).
    subroutine global_energies()
      real(wp) :: loc(6), tot(6)
      call energy_totals(ps, en)
      loc = [en%ke, en%ke0, en%w_int, en%w_plastic, en%w_ext, en%w_contact]
      call MPI_Allreduce(loc, tot, 6, MPI_DOUBLE_PRECISION, MPI_SUM, comm)
      en%ke = tot(1)
      en%ke0 = tot(2)
      en%w_int = tot(3)
      en%w_plastic = tot(4)
      en%w_ext = tot(5)
      en%w_contact = tot(6)
      en%residual = en%ke + en%w_int - en%ke0 - en%w_ext - en%w_contact
      en%scale = max(en%ke0, en%ke, abs(en%w_int), abs(en%w_ext), abs(en%w_contact), &
        tiny(1.0_wp))
    end subroutine global_energies

    !> The largest kappa of every solid over the ranks: the same step everywhere.
    subroutine global_kappa()
      integer :: kk
      real(wp) :: v
      do kk = 1, size(ps)
        call MPI_Allreduce(ps(kk)%kappa, v, 1, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
        ps(kk)%kappa = v
      end do
    end subroutine global_kappa

    !> The step's contact statistics over the ranks (counts and force summed, the rest the
    !! largest; the tracked edge in contact on its owner).
    subroutine global_contact_stats(c)
      type(contact_stats_t), intent(inout) :: c
      integer :: ni(4), nt(4)
      real(wp) :: rs(1), rt(1), rm(3), rmt(3)
      ni = [c%n_contact, c%n_flagged, c%n_cmp_det, merge(1, 0, c%edge_in_contact)]
      call MPI_Allreduce(ni, nt, 4, MPI_INTEGER, MPI_SUM, comm)
      rs = c%force_normal
      call MPI_Allreduce(rs, rt, 1, MPI_DOUBLE_PRECISION, MPI_SUM, comm)
      rm = [c%radius, c%pen_before, c%pen_after]
      call MPI_Allreduce(rm, rmt, 3, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
      c%n_contact = nt(1)
      c%n_flagged = nt(2)
      c%n_cmp_det = nt(3)
      c%edge_in_contact = nt(4) > 0
      c%force_normal = rt(1)
      c%radius = rmt(1)
      c%pen_before = rmt(2)
      c%pen_after = rmt(3)
    end subroutine global_contact_stats

    !> The most particles each pair flagged in one step, over all ranks.
    subroutine global_flagged()
      integer :: nf(size(pairs)), nft(size(pairs)), kk
      if (size(pairs) == 0) return
      nf = [(pairs(kk)%step%n_flagged, kk = 1, size(pairs))]
      call MPI_Allreduce(nf, nft, size(pairs), MPI_INTEGER, MPI_SUM, comm)
      flag_max = max(flag_max, int(nft, i64))
    end subroutine global_flagged

    !> The pairs' counters summed over the ranks (most in one step: the largest).
    subroutine global_counters()
      integer :: kk
      integer(i64) :: a(5), b(5)
      do kk = 1, size(pairs)
        associate (c => pairs(kk)%count)
          a = [c%screened, c%evaluated, c%detected, c%contacts, c%skipped]
          call MPI_Allreduce(a, b, 5, MPI_INTEGER8, MPI_SUM, comm)
          c%screened = b(1)
          c%evaluated = b(2)
          c%detected = b(3)
          c%contacts = b(4)
          c%skipped = b(5)
          ! (the most flagged in one step over all ranks: global_flagged)
          c%detected_max = flag_max(kk)
        end associate
      end do
    end subroutine global_counters

    !> The bytes the halo exchanges moved, over all ranks, per step (log line of rank 0).
    subroutine halo_report()
      integer(i64) :: loc(2), tot(2)
      integer :: kk, ng(2), ngt(2)
      character(len=200) :: line
      loc = 0
      ng = 0
      do kk = 1, size(ps)
        loc = loc + [parts(kk)%plan%bytes_nodes, parts(kk)%plan%bytes_points]
        ng = ng + [ps(kk)%np - size(ps(kk)%own_n), ps(kk)%nq - size(ps(kk)%own_q)]
      end do
      call MPI_Allreduce(loc, tot, 2, MPI_INTEGER8, MPI_SUM, comm)
      call MPI_Allreduce(ng, ngt, 2, MPI_INTEGER, MPI_SUM, comm)
      if (root) then
        write(line, '(a,i0,a,i0,a,i0,a,es10.3,a,es10.3,a)') 'summary: MPI: ', nranks, &
          ' rank(s), ', ngt(1), ' ghost nodes and ', ngt(2), ' ghost points; the halos '// &
          'moved ', real(tot(1), wp)/max(r%n, 1), ' B (nodes) and ', &
          real(tot(2), wp)/max(r%n, 1), ' B (points) per step'
        write(*, '(a)') trim(line)
      end if
      call contact_ghosts_report()
    end subroutine halo_report

    !> Contact with deforming masters: the refreshes of the ghost sets, the ghost master
    !! particles (mean over the passes, summed over the ranks) and the bytes contact's
    !! messages moved per step, over all ranks.
    subroutine contact_ghosts_report()
      integer :: kk, nref(2)
      real(wp) :: gh(2), ght(2)
      integer(i64) :: b(1), bt(1)
      character(len=240) :: line
      b = ranks%bytes
      call MPI_Allreduce(b, bt, 1, MPI_INTEGER8, MPI_SUM, comm)
      do kk = 1, size(pairs)
        if (.not. allocated(pairs(kk)%dist)) cycle
        call contact_dist_report(pairs(kk), nref, gh)
        call MPI_Allreduce(gh, ght, 2, MPI_DOUBLE_PRECISION, MPI_SUM, comm)
        if (.not. root) cycle
        write(line, '(a,i0,a,i0,a,i0,a,f0.1,a,f0.1,a,es10.3,a)') 'summary: MPI: contact ', &
          kk, ': ghost sets refreshed ', nref(1), ' and ', nref(2), &
          ' times (slave, master as masters), ', ght(1), ' and ', ght(2), &
          ' ghost particles on average; contact moved ', real(bt(1), wp)/max(r%n, 1), &
          ' B per step'
        write(*, '(a)') trim(line)
      end do
    end subroutine contact_ghosts_report

    !> A failure on any rank fails every rank, with the lowest failing rank's reason.
    subroutine agree_failure()
      integer :: mine, first, n
      character(len=:), allocatable :: buf
      mine = merge(me, nranks, r%failed)
      call MPI_Allreduce(mine, first, 1, MPI_INTEGER, MPI_MIN, comm)
      if (first == nranks) return
      n = 0
      if (me == first) n = len(r%reason)
      call MPI_Bcast(n, 1, MPI_INTEGER, first, comm)
      allocate(character(len=n) :: buf)
      if (me == first) buf = r%reason
      call MPI_Bcast(buf, n, MPI_CHARACTER, first, comm)
      r%failed = .true.
      r%reason = buf//' (rank '//itoa(first)//')'
    end subroutine agree_failure

    !> Is a snapshot time within this step's reach (then rank 0 needs the state)?
    logical function snapshot_near()
      integer :: j
      snapshot_near = .false.
      do j = 1, deck%solver%nsnap
        if (abs(deck%solver%snapshot_times(j) - r%t) <= 0.5_wp*r%dt*(1.0_wp + landing_slack)) &
          snapshot_near = .true.
      end do
    end function snapshot_near

    !> Rank 0 wrote a snapshot (it has more than nbefore): every rank restarts its contact
    !! impulse sums, as the snapshot restarted the gathered ones.
    subroutine reset_impulses_if_written(nbefore)
      integer, intent(in) :: nbefore
      integer :: flag, kk
      flag = 0
      if (root) flag = merge(1, 0, out%nsnap_done > nbefore)
      call MPI_Bcast(flag, 1, MPI_INTEGER, 0, comm)
      if (flag == 0) return
      do kk = 1, size(ps)
        ps(kk)%ipoint = 0.0_wp
        ps(kk)%ipoint_time = 0.0_wp
      end do
    end subroutine reset_impulses_if_written

    !> The state at t = 0 (forces at u = 0), its snapshot, history row and log line.
    subroutine run_start()
      integer :: kk
      do kk = 1, size(ps)
        call solid_points_force(ps(kk), r%dt, bad_q, bad_j)
        call halo_pstab(kk)
        call solid_nodes_force(ps(kk))
        where (ps(kk)%pres)
          ps(kk)%v = ps(kk)%vpres
          ps(kk)%a = 0.0_wp
        end where
        call halo_va(kk)
      end do
      call global_energies()
      call gather_all()
      if (root) then
        call snapshots_due(out, deck, r, pairs_whole, gs, err)
        call history_push(out%hist, history_row(r, en, gs(1)))
        call log_header()
        call log_line(r, en)
      end if
      call reset_impulses_if_written(0)
    end subroutine run_start

    !> A checkpoint of the state after step r%n (&output checkpoint_every), written by rank
    !! 0 from the whole solids gathered, the solids' energies and the pairs' counters summed
    !! over the ranks: the serial layout, which any number of ranks can restart from (the
    !! ghost sets of contact and skip_far's schedule start afresh, which is exact).
    subroutine write_checkpoint()
      integer :: kk
      real(wp) :: e(8), et(8)
      type(contact_counters_t), allocatable :: keep(:)
      logical :: skip(size(pairs))
      do kk = 1, size(ps)
        call gather_solid(ps(kk), parts(kk)%lp, gs(kk), full=.true.)
        associate (p => ps(kk))
          e = [p%ke0, p%ke, p%w_int, p%w_plastic, p%w_bc, p%w_ext, p%w_contact, p%e_stab]
        end associate
        call MPI_Reduce(e, et, 8, MPI_DOUBLE_PRECISION, MPI_SUM, 0, comm)
        if (.not. root) cycle
        associate (g => gs(kk))
          g%ke0 = et(1)
          g%ke = et(2)
          g%w_int = et(3)
          g%w_plastic = et(4)
          g%w_bc = et(5)
          g%w_ext = et(6)
          g%w_contact = et(7)
          g%e_stab = et(8)
          g%kappa = ps(kk)%kappa
        end associate
      end do
      allocate(keep(size(pairs)))
      do kk = 1, size(pairs)
        keep(kk) = pairs(kk)%count
      end do
      call global_counters()
      if (root) then
        ! (skip_far's schedule is each rank's own: not written)
        skip = [(pairs(kk)%side(1)%skip_far, kk = 1, size(pairs))]
        do kk = 1, size(pairs)
          pairs(kk)%side(1)%skip_far = .false.
        end do
        call run_files_checkpoint(out, deck, bodies, r, gs, pairs, r%t_loop + &
          (omp_get_wtime() - t_loop0), err)
        do kk = 1, size(pairs)
          pairs(kk)%side(1)%skip_far = skip(kk)
        end do
      end if
      do kk = 1, size(pairs)
        pairs(kk)%count = keep(kk)
      end do
    end subroutine write_checkpoint

    !> Part solid k's state from the whole solid g read from a checkpoint (every local
    !! node and point, ghosts too: the exchanges need not run before the first step); the
    !! energies, sums over the ranks, on rank 0.
    subroutine restart_part(k)
      integer, intent(in) :: k
      associate (p => ps(k), g => gs(k), n => parts(k)%lp%nglob, q => parts(k)%lp%qglob)
        p%d = g%d(:, n)
        p%v = g%v(:, n)
        p%a = g%a(:, n)
        p%freac_old = g%freac_old(:, n)
        p%freac = p%freac_old
        p%ipoint = g%ipoint(:, n)
        p%ipoint_time = g%ipoint_time
        p%f = g%f(:, q)
        p%f_old = p%f
        p%p = g%p(:, q)
        p%p_old = p%p
        p%st%tau = g%st%tau(:, q)
        p%st%alpha = g%st%alpha(:, q)
        p%st%epsbar = g%st%epsbar(q)
        p%st%epsdot = g%st%epsdot(q)
        p%kappa = g%kappa
        p%dt_cal = g%dt_cal
        p%ke0 = merge(g%ke0, 0.0_wp, root)
        p%ke = merge(g%ke, 0.0_wp, root)
        p%w_int = merge(g%w_int, 0.0_wp, root)
        p%w_plastic = merge(g%w_plastic, 0.0_wp, root)
        p%w_bc = merge(g%w_bc, 0.0_wp, root)
        p%w_ext = merge(g%w_ext, 0.0_wp, root)
        p%w_contact = merge(g%w_contact, 0.0_wp, root)
        p%e_stab = merge(g%e_stab, 0.0_wp, root)
      end associate
    end subroutine restart_part

    !> Every solid's owned values into rank 0's whole solids (for output and measures).
    subroutine gather_all()
      integer :: kk
      do kk = 1, size(ps)
        call gather_solid(ps(kk), parts(kk)%lp, gs(kk))
      end do
    end subroutine gather_all

    !> The owned values of part solid p into rank 0's whole solid g: what output and the
    !! measures need, and with full what a checkpoint holds besides (a, the reactions, P,
    !! the back stress, the plastic strain rate).
    subroutine gather_solid(p, lp, g, full)
      type(solid_t), intent(in) :: p
      type(local_part_t), intent(in) :: lp
      type(solid_t), intent(inout) :: g
      logical, intent(in), optional :: full
      real(wp), allocatable :: sn(:, :), sq(:, :), rn(:, :), rq(:, :)
      integer, allocatable :: idn(:), idq(:), rin(:), riq(:), cn(:), cq(:), dn(:), dq(:)
      integer :: j, no, nqo, i, mn, mq
      logical :: all_state
      all_state = .false.
      if (present(full)) all_state = full
      mn = merge(10, 6, all_state)
      mq = merge(20, 10, all_state)
      no = size(p%own_n)
      nqo = size(p%own_q)
      allocate(sn(mn, no), sq(mq, nqo), idn(no), idq(nqo), cn(nranks), cq(nranks), &
        dn(nranks), dq(nranks))
      do j = 1, no
        i = p%own_n(j)
        idn(j) = lp%nglob(i)
        sn(1:6, j) = [p%d(:, i), p%v(:, i), p%ipoint(:, i)]
        if (all_state) sn(7:10, j) = [p%a(:, i), p%freac_old(:, i)]
      end do
      do j = 1, nqo
        i = p%own_q(j)
        idq(j) = lp%qglob(i)
        sq(1:10, j) = [p%f(:, i), p%st%tau(:, i), p%st%epsbar(i)]
        if (all_state) sq(11:20, j) = [p%p(:, i), p%st%alpha(:, i), p%st%epsdot(i)]
      end do
      call MPI_Gather(no, 1, MPI_INTEGER, cn, 1, MPI_INTEGER, 0, comm)
      call MPI_Gather(nqo, 1, MPI_INTEGER, cq, 1, MPI_INTEGER, 0, comm)
      if (root) then
        dn(1) = 0
        dq(1) = 0
        do j = 2, nranks
          dn(j) = dn(j - 1) + cn(j - 1)
          dq(j) = dq(j - 1) + cq(j - 1)
        end do
        allocate(rin(sum(cn)), riq(sum(cq)), rn(mn, sum(cn)), rq(mq, sum(cq)))
      else
        allocate(rin(1), riq(1), rn(mn, 1), rq(mq, 1))
      end if
      call MPI_Gatherv(idn, no, MPI_INTEGER, rin, cn, dn, MPI_INTEGER, 0, comm)
      call MPI_Gatherv(idq, nqo, MPI_INTEGER, riq, cq, dq, MPI_INTEGER, 0, comm)
      call MPI_Gatherv(sn, mn*no, MPI_DOUBLE_PRECISION, rn, mn*cn, mn*dn, &
        MPI_DOUBLE_PRECISION, 0, comm)
      call MPI_Gatherv(sq, mq*nqo, MPI_DOUBLE_PRECISION, rq, mq*cq, mq*dq, &
        MPI_DOUBLE_PRECISION, 0, comm)
      if (.not. root) return
      do j = 1, size(rin)
        g%d(:, rin(j)) = rn(1:2, j)
        g%v(:, rin(j)) = rn(3:4, j)
        g%ipoint(:, rin(j)) = rn(5:6, j)
        if (.not. all_state) cycle
        g%a(:, rin(j)) = rn(7:8, j)
        g%freac_old(:, rin(j)) = rn(9:10, j)
      end do
      do j = 1, size(riq)
        g%f(:, riq(j)) = rq(1:5, j)
        g%st%tau(:, riq(j)) = rq(6:9, j)
        g%st%epsbar(riq(j)) = rq(10, j)
        if (.not. all_state) cycle
        g%p(:, riq(j)) = rq(11:15, j)
        g%st%alpha(:, riq(j)) = rq(16:19, j)
        g%st%epsdot(riq(j)) = rq(20, j)
      end do
      g%ipoint_time = p%ipoint_time
    end subroutine gather_solid
  end subroutine run_dynamic_mpi

  !> Contact's exchanges for a part of an RKPM slave (contact_pair_m side_t%exchange): the
  !! ghost particles' point forces f, or the solid's ghost nodes' corrected d and a.
  subroutine contact_exchange(id, what, sol, f)
    integer, intent(in) :: id, what
    type(solid_t), intent(inout) :: sol
    real(wp), intent(inout) :: f(:, :)
    select case (what)
    case (exchange_forces)
      call halo_nodes(parts(id)%plan, f)
    case (exchange_state)
      call halo_two(id, sol%d, sol%a)
    end select
  end subroutine contact_exchange

  !> The ghost nodes' values of two nodal arrays x, y (2, local nodes) of part k from their
  !! owners, in one exchange.
  subroutine halo_two(k, x, y)
    integer, intent(in) :: k
    real(wp), intent(inout) :: x(:, :), y(:, :)
    parts(k)%w(1:2, :) = x
    parts(k)%w(3:4, :) = y
    call halo_nodes(parts(k)%plan, parts(k)%w)
    x = parts(k)%w(1:2, :)
    y = parts(k)%w(3:4, :)
  end subroutine halo_two

  !> An error on any rank is an error on every rank (the others get a pointer to it).
  logical function any_error(comm, err) result(yes)
    type(MPI_Comm), intent(in) :: comm
    type(error_t), allocatable, intent(inout) :: err
    integer :: mine, n
    mine = merge(1, 0, allocated(err))
    call MPI_Allreduce(mine, n, 1, MPI_INTEGER, MPI_SUM, comm)
    yes = n > 0
    if (yes .and. .not. allocated(err)) call set_error(err, 'another rank failed (its '// &
      'message is on its standard error)')
  end function any_error
end module mpi_run_m
