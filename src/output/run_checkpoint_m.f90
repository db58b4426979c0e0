!> Checkpoints of a dynamic run (&output checkpoint_every) and the restart from them
!! (mfcd --restart CHECKPOINT.h5 DECK.nml). Layout: doc/output.md, "Checkpoints".
!!
!! A checkpoint holds what carries over from one step to the next, so that the restarted
!! run takes the same steps as the run that was interrupted, bit for bit with the same
!! number of threads. The step (explicit_driver_m) reads, before writing them again:
!!  - per solid: the coefficients d, v, a (eq. 64 predicts from them), F and P (they become
!!    F_n, P_n of the step: rate of deformation, internal work), the reactions of the
!!    kinematic conditions (their work is a trapezoid over the step), the material state
!!    (tau, alpha, epsbar, epsdot), the energy accounts, the critical-step estimate
!!    (kappa, where it is, its calibration dt_cal) and the wall-clock timers;
!!  - the run record: step, time, last dt, the step control and its extremes, the energy
!!    guard's counter, node and point counts, contact extremes, impulse and edge events;
!!  - per contact pair, the counters summed over the run;
!!  - the output: every /history row so far, and how many of the deck's snapshots are done.
!! What the step computes afresh before reading it is not saved: d_old, a_old and fcon
!! (solid_predict), F_old and P_old (copied from F and P), D, W12, the plastic work of the
!! step, the stabilization stresses (from d; their energy is saved with the others for the
!! restart's first log line), f_int, the reactions of the step, the physical positions,
!! and every contact work array (positions from d, detection and forces each step; a
!! deformable master's cloud and surface are rebuilt from d). f_ext is zero from set-up on.
!! Everything that depends on the reference configuration only (tables, masses, the power
!! iteration, health limits, rigid masters) is rebuilt from the deck and the bodies,
!! identically: the checkpoint refuses a deck whose text differs and bodies whose particles
!! differ.
module run_checkpoint_m
  use omp_lib, only: omp_get_wtime, omp_get_max_threads
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa, join_names
  use version_m, only: code_version, git_commit
  use deck_m, only: deck_t
  use body_m, only: body_t
  use solid_m, only: solid_t, solid_quiet_blocks, state_fields, solid_field_rows, &
    solid_get_field, solid_put_field, solid_state_derived, solid_energies, solid_set_energies, &
    solid_account_sums
  use exact_sum_m, only: exact_sum_t, exact_value, exact_add, exact_pack, exact_unpack, &
    exact_pack_size, exact_allsum_many
  use rank_comm_m, only: rank_comm_t, share_first
  use contact_pair_m, only: contact_pair_t
  use run_report_m, only: run_record_t
  use dynamic_output_m, only: history_t, history_width, history_geometry, output_rows
  use run_output_m, only: timestamp
  use hdf5_io_m, only: h5file_t, h5_create, h5_close, h5_group, h5_write, h5_attr, h5_text, &
    h5_write_rows, h5_read_rows, &
    h5_open_read, h5_has, h5_has_attr, h5_shape, h5_read, h5_read_attr, h5_read_text
  use log_m, only: log_print
  implicit none
  private
  public :: checkpoint_write, checkpoint_check, checkpoint_read, checkpoint_info_t, &
    checkpoint_write_fields, checkpoint_read_part, body_fingerprints

  !> The root attribute 'format' of every checkpoint, and the layout version this mfcd
  !! writes and reads (raise it when the layout changes; 3: with work_points, work_nodes;
  !! 4: the bodies' sum_x_vol exact sums, body_fingerprints).
  character(len=*), parameter :: checkpoint_kind = 'mfcd checkpoint'
  integer, parameter :: checkpoint_format = 4

  !> What a checkpoint says about itself (root attributes).
  type :: checkpoint_info_t
    integer :: step = 0                   !< the step it was written at
    real(wp) :: time = 0.0_wp             !< its time (s)
    integer :: threads = 0                !< OpenMP threads of the run that wrote it
    character(len=:), allocatable :: git  !< git commit of the mfcd that wrote it
  end type checkpoint_info_t

  character(len=*), parameter :: skip_due_text = 'travel at which each particle is '// &
    'screened again', skip_d_text = 'coefficients at the last screening'

contains

  !> Write the state of the run after step r%n to a new file at path (created exclusively;
  !! the caller renames it over the previous checkpoint). t_loop: seconds in the time loop
  !! so far; snap_times: the times of the deck snapshots written so far (nsnap_done of them).
  subroutine checkpoint_write(path, deck, bodies, r, solids, pairs, hist, nsnap_done, &
    snap_times, t_loop, err, fields)
    character(len=*), intent(in) :: path
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(in) :: solids(:)
    type(contact_pair_t), intent(in) :: pairs(:)
    type(history_t), intent(in) :: hist
    integer, intent(in) :: nsnap_done
    real(wp), intent(in) :: snap_times(:), t_loop
    type(error_t), allocatable, intent(inout) :: err
    !> .false.: without the solids' state fields, which the ranks write into the file
    !! afterwards, each its part's rows (checkpoint_write_fields)
    logical, intent(in), optional :: fields
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    integer :: k
    logical :: with_fields
    with_fields = .true.
    if (present(fields)) with_fields = fields
    call h5_create(f, path, err)
    if (allocated(err)) return
    call h5_attr(f, '/', 'format', checkpoint_kind, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'format_version', checkpoint_format, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'code_version', code_version, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'git_commit', git_commit, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'deck_path', deck%path, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'created', timestamp(), err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'step', r%n, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'time', r%t, err)
    if (.not. allocated(err)) call h5_attr(f, '/', 'threads', omp_get_max_threads(), err)
    if (.not. allocated(err)) call h5_text(f, '/deck', deck%text, err)
    if (.not. allocated(err)) call write_bodies_fingerprint(f, bodies, err)
    if (.not. allocated(err)) call write_record(f, r, t_loop, err)
    if (.not. allocated(err)) call h5_group(f, '/solids', err)
    do k = 1, size(solids)
      if (.not. allocated(err)) call write_solid(f, solids(k), with_fields, err)
    end do
    if (.not. allocated(err)) call h5_group(f, '/contacts', err)
    do k = 1, size(pairs)
      if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k), &
        [pairs(k)%count%screened, pairs(k)%count%evaluated, pairs(k)%count%detected, &
        pairs(k)%count%contacts], '1', err, 'counters since t = 0: screened, '// &
        'evaluated, detected, contacts')
      associate (c => pairs(k)%count)
        if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k)//'_compare', &
          [c%detected_max, c%cmp_det, c%cmp_gap, c%cmp_buffer, c%cmp_missed, c%cmp_det_max, &
          c%cmp_gap_max], '1', err, 'counters since t = 0: most flagged in a step, '// &
          'det(M) flagged, gap flagged, buffer zone, missed, most of each in a step')
        if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k)// &
          '_buffer_gap', [c%buffer_gap_sum, c%buffer_gap_max], 'm', err, &
          'buffer-zone gaps since t = 0: sum, largest')
        if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k)// &
          '_buffer_gap_exact', exact_pack(c%buffer_gap_exact), '1', err, 'buffer-zone '// &
          'gaps since t = 0, their exact sum (as _w_friction_exact), to go on adding to')
        if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k)// &
          '_detect_time', [c%t_detect], 's', err, 'wall time in the detector since t = 0')
        if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k)// &
          '_pair_time', [c%t_pair], 's', err, 'wall time in the pair''s correction since '// &
          't = 0')
        if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k)// &
          '_w_friction', [c%w_friction], 'J', err, 'friction work since t = 0')
        if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k)// &
          '_w_friction_exact', exact_pack(c%w_friction_sum), '1', err, 'friction work '// &
          'since t = 0, its exact sum (exact_sum_m: limbs of 32 bits from 2^-1152, then '// &
          'the count of terms not finite), to go on adding to without rounding')
        if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k)// &
          '_self_unsure', [c%self_unsure], '1', err, '3D self-contact flags with g < 0 '// &
          'left without contact since t = 0, their sign not sure')
      end associate
      ! skip_far's state, so that a restarted run skips what the uninterrupted one skips
      associate (s => pairs(k)%side(1))
        if (s%skip_far .and. .not. allocated(err)) then
          call h5_write(f, '/contacts/contact'//itoa(k)//'_skipped', &
            [pairs(k)%count%skipped], '1', err, 'screenings skipped since t = 0 (skip_far)')
          if (.not. allocated(err)) call h5_write(f, '/contacts/contact'//itoa(k)// &
            '_skip_travel', [s%travel], 'm', err, 'bound on the particles'' motion since t = 0')
          ! (on ranks each rank writes its own particles' rows: checkpoint_write_fields)
          if (with_fields .and. .not. allocated(err)) call h5_write(f, '/contacts/contact'// &
            itoa(k)//'_skip_due', s%due, 'm', err, skip_due_text)
          if (with_fields .and. .not. allocated(err)) call h5_write(f, '/contacts/contact'// &
            itoa(k)//'_skip_d', s%d_scr, 'm', err, skip_d_text)
        end if
      end associate
    end do
    if (.not. allocated(err)) call h5_group(f, '/output', err)
    if (.not. allocated(err)) call h5_attr(f, '/output', 'nsnap_done', nsnap_done, err)
    if (.not. allocated(err)) call h5_write(f, '/output/snapshot_times', snap_times, 's', &
      err, 'times of the deck snapshots written so far (0001, 0002, ...)')
    if (.not. allocated(err)) call h5_write(f, '/output/history', hist%rows(:, 1:hist%n), &
      'as /history', err, 'every /history row so far (columns: attribute history_columns)')
    if (.not. allocated(err)) call h5_attr(f, '/output/history', 'history_columns', &
      join_names(hist%paths), err)
    call h5_close(f, e2)
    if (allocated(e2) .and. .not. allocated(err)) call move_alloc(e2, err)
  end subroutine checkpoint_write

  !> The run record and its step control as attributes of /record.
  subroutine write_record(f, r, t_loop, err)
    type(h5file_t), intent(in) :: f
    type(run_record_t), intent(in) :: r
    real(wp), intent(in) :: t_loop
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: g = '/record'
    call h5_group(f, g, err)
    if (allocated(err)) return
    call h5_attr(f, g, 'n', r%n, err)
    if (.not. allocated(err)) call h5_attr(f, g, 't', r%t, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'dt', r%dt, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'nsteps_est', r%nsteps_est, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'energy_over', r%energy_over, err)
    if (.not. allocated(err)) call h5_write(f, g//'/node_point_steps', &
      [r%node_steps, r%point_steps], '1', err, 'nodes x steps, integration points x steps')
    if (.not. allocated(err)) call h5_write(f, g//'/subcycle_counts', [r%sub%steps, &
      r%sub%substeps, r%sub%fine_evals, r%sub%uniform_evals, int(r%sub%m_max, i64)], '1', &
      err, 'subcycled steps, sub-steps, fine point updates, unsplit updates, most sub-steps')
    if (.not. allocated(err)) call h5_attr(f, g, 'wall', omp_get_wtime() - r%wall0, err)
    if (.not. allocated(err)) call h5_attr(f, g, 't_loop', t_loop, err)
    if (.not. allocated(err)) call h5_attr(f, g, 't_contact', r%t_contact, err)
    if (.not. allocated(err)) call h5_attr(f, g, 't_output', r%t_output, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'pen_max', r%pen_max, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'impulse', r%impulse, err)
    if (.not. allocated(err)) call h5_attr(f, g, 't_edge_first', r%t_edge_first, err)
    if (.not. allocated(err)) call h5_attr(f, g, 't_edge_sep', r%t_edge_sep, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'edge_prev', merge(1, 0, r%edge_prev), err)
    ! what contact did in the last step (history row and log line of a restart at the end)
    if (.not. allocated(err)) call h5_attr(f, g, 'contact_n', r%contact%n_contact, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'contact_force_radius_pen', &
      [r%contact%force_normal, r%contact%radius, r%contact%pen_before, &
      r%contact%pen_after], err)
    if (.not. allocated(err)) call h5_attr(f, g, 'contact_edge', &
      merge(1, 0, r%contact%edge_in_contact), err)
    associate (c => r%step)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_adaptive', merge(1, 0, c%adaptive), &
        err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_cfl_fixed_dtc0', &
        [c%cfl, c%dt_fixed, c%dtc0], err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_dtc', c%dtc, err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_solid', c%solid, err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_point', c%point, err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_solid_min', c%solid_min, err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_point_min', c%point_min, err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_dt_min_max_t', &
        [c%dt_min, c%dt_max, c%t_dt_min], err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_dt_min_taken', &
        [c%dt_min_taken, c%t_dt_min_taken], err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_dtc_min', c%dtc_min, err)
      if (.not. allocated(err)) call h5_attr(f, g, 'step_n_over', c%n_over, err)
    end associate
  end subroutine write_record

  !> /solids/<name>: the state of one solid that carries over between steps (with fields
  !! its state fields, else its sizes and scalars only).
  subroutine write_solid(f, s, fields, err)
    type(h5file_t), intent(in) :: f
    type(solid_t), intent(in) :: s
    logical, intent(in) :: fields
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: g
    type(exact_sum_t) :: e(8)
    integer :: k
    g = '/solids/'//trim(s%name)
    call h5_group(f, g, err)
    if (allocated(err)) return
    call h5_attr(f, g, 'np', s%np, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'nq', s%nq, err)
    if (fields .and. .not. allocated(err)) call write_fields(f, g, s, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'contact_impulse_time', s%state%ipoint_time, err)
    ! the energy accounts: the exact sums of a whole solid's entries (solid_account_sums),
    ! the numbers the history records; a rank 0's solid without fields has them set
    ! already (mpi_checkpoint: the sums over the ranks' parts)
    if (fields) then
      e = exact_sum_t()
      call solid_account_sums(s, e)
      if (.not. allocated(err)) call h5_attr(f, g, 'energies', [(exact_value(e(k)), &
        k = 1, 8)], err)
    else
      if (.not. allocated(err)) call h5_attr(f, g, 'energies', solid_energies(s), err)
    end if
    if (.not. allocated(err)) call h5_attr(f, g, 'kappa_dt_cal', [s%kappa, s%dt_cal], err)
    if (.not. allocated(err)) call h5_attr(f, g, 'kappa_q', s%kappa_q, err)
    if (.not. allocated(err)) call h5_attr(f, g, 'wall', s%acc%wall, err)
    ! quiet points (&solver skip_quiet): which are active, which nodes are disturbed, so
    ! that a restarted run skips what the uninterrupted one skips
    if (s%quiet_on .and. .not. allocated(err)) then
      call h5_attr(f, g, 'quiet_all_awake_skipped', [merge(1.0_wp, 0.0_wp, s%all_awake), &
        real(s%acc%quiet_skipped, wp)], err)
      if (.not. allocated(err)) call h5_write(f, g//'/quiet_awake', merge(1.0_wp, 0.0_wp, &
        s%awake), '1', err, 'node disturbed from the uniform translation: 1 (np)')
      if (.not. allocated(err)) call h5_write(f, g//'/quiet_active', merge(1.0_wp, 0.0_wp, &
        s%qact), '1', err, 'integration point active: 1 (nq)')
    end if
  end subroutine write_solid

  !> The state fields of the solids into their groups /solids/<name> (made by
  !! checkpoint_write with fields = .false.): on MPI ranks, every rank its part's rows into
  !! the file opened on all with MPI-IO, collectively.
  subroutine checkpoint_write_fields(f, solids, pairs, err)
    type(h5file_t), intent(in) :: f
    type(solid_t), intent(in) :: solids(:)
    type(contact_pair_t), intent(in) :: pairs(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    do k = 1, size(solids)
      if (.not. allocated(err)) call write_fields(f, '/solids/'//trim(solids(k)%name), &
        solids(k), err)
    end do
    do k = 1, size(pairs)
      if (.not. allocated(err)) call write_skip_rows(f, k, pairs(k), solids, err)
    end do
  end subroutine checkpoint_write_fields

  !> skip_far's schedule of pair p (number k), the datasets /contacts/contact<k>_skip_due and
  !! _skip_d of a serial checkpoint, from the ranks: each writes the rows of the slave
  !! particles it owns by their numbers in the whole body, collectively. A rank keeps the
  !! schedule of its own particles as the serial run does (its passes and add_travel look at
  !! those; the bound on the motion is taken over the ranks), so the rows are the serial
  !! arrays, and a restart on any number of ranks, or by the serial program, skips what the
  !! uninterrupted run skips.
  subroutine write_skip_rows(f, k, p, solids, err)
    type(h5file_t), intent(in) :: f
    integer, intent(in) :: k
    type(contact_pair_t), intent(in) :: p
    type(solid_t), intent(in) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: own(:), gn(:), oq(:), gq(:)
    real(wp), allocatable :: due(:), d(:, :)
    integer :: n, nqw, j
    character(len=:), allocatable :: c
    associate (s => p%side(1))
      if (.not. (s%skip_far .and. allocated(s%due))) return
      if (allocated(p%dist)) then
        ! (a deforming master's or self-contact's side: the rank's own particles first,
        ! by their numbers in the whole body)
        own = [(j, j = 1, p%dist%side(1)%nown)]
        gn = s%glob(own)
        n = s%np_whole
      else
        ! (a rigid master's slave side: over the part's nodes)
        call output_rows(solids(s%isolid), own, gn, n, oq, gq, nqw)
      end if
      due = s%due(own)
      d = s%d_scr(:, own)
      c = '/contacts/contact'//itoa(k)
      call h5_write_rows(f, c//'_skip_due', due, gn, n, 'm', err, skip_due_text)
      if (.not. allocated(err)) call h5_write_rows(f, c//'_skip_d', d, gn, n, 'm', err, &
        skip_d_text)
    end associate
  end subroutine write_skip_rows

  !> Each state field (state_fields) of solid s as dataset g/<name>: (rows, np) on nodes,
  !! (rows, nq) on integration points, one row as a 1-D dataset; the rows of the whole
  !! solid, or of a rank's part's own nodes and points by their global numbers.
  subroutine write_fields(f, g, s, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: g
    type(solid_t), intent(in) :: s
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: buf(:, :), row(:)
    integer, allocatable :: on(:), gn(:), oq(:), gq(:)
    integer :: rows, nn, nqw, k
    character(len=:), allocatable :: dims
    call output_rows(s, on, gn, nn, oq, gq, nqw)
    do k = 1, size(state_fields)
      if (allocated(err)) return
      associate (fk => state_fields(k))
        rows = solid_field_rows(s, k)
        dims = merge('np', 'nq', fk%nodal)
        if (fk%nodal) then
          allocate(buf(rows, size(on)))
          call solid_get_field(s, k, buf, on)
        else
          allocate(buf(rows, size(oq)))
          call solid_get_field(s, k, buf, oq)
        end if
        if (rows == 1) then
          row = buf(1, :)
          if (fk%nodal) call h5_write_rows(f, g//'/'//trim(fk%name), row, gn, nn, &
            trim(fk%unit), err, trim(fk%what)//' ('//dims//')')
          if (.not. fk%nodal) call h5_write_rows(f, g//'/'//trim(fk%name), row, gq, nqw, &
            trim(fk%unit), err, trim(fk%what)//' ('//dims//')')
        else
          if (fk%nodal) call h5_write_rows(f, g//'/'//trim(fk%name), buf, gn, nn, &
            trim(fk%unit), err, trim(fk%what)//' ('//itoa(rows)//', '//dims//')')
          if (.not. fk%nodal) call h5_write_rows(f, g//'/'//trim(fk%name), buf, gq, nqw, &
            trim(fk%unit), err, trim(fk%what)//' ('//itoa(rows)//', '//dims//')')
        end if
        deallocate(buf)
      end associate
    end do
  end subroutine write_fields

  !> /bodies/<name>: particle count and sums of positions and volumes of every body, to
  !! recognise a body that changed under an unchanged deck (a particle file).
  subroutine write_bodies_fingerprint(f, bodies, err)
    type(h5file_t), intent(in) :: f
    type(body_t), intent(in) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    character(len=:), allocatable :: g
    call h5_group(f, '/bodies', err)
    do k = 1, size(bodies)
      if (allocated(err)) return
      g = '/bodies/'//trim(bodies(k)%name)
      call h5_group(f, g, err)
      if (.not. allocated(err)) call h5_attr(f, g, 'np', bodies(k)%np, err)
      if (.not. allocated(err)) call h5_attr(f, g, 'sum_x_vol', bodies(k)%fingerprint, err)
    end do
  end subroutine write_bodies_fingerprint

  !> Each body's fingerprint (body_t): the exact sums of its particles' coordinates and of
  !! their volumes, each rank adding its share of the particles (a contiguous run of the
  !! numbering, n*r/nranks + 1 ... n*(r + 1)/nranks for rank r) and one exact sum over the
  !! ranks making the whole body's, the same bits on every rank and for any rank count
  !! (the plain sums before checkpoint format 4 were not: their rounding followed the
  !! order). Collective (comm: the ranks; single_rank_t for a serial run).
  subroutine body_fingerprints(bodies, comm)
    type(body_t), intent(inout) :: bodies(:)
    class(rank_comm_t), intent(inout) :: comm
    type(exact_sum_t) :: a(2*size(bodies))
    real(wp) :: v(2*size(bodies))
    integer :: k, i, j
    do k = 1, size(bodies)
      associate (b => bodies(k))
        if (b%held_share) then
          ! (made as the share: build_bodies on ranks)
          do i = 1, size(b%x, 2)
            do j = 1, size(b%x, 1)
              call exact_add(a(2*k - 1), b%x(j, i))
            end do
            call exact_add(a(2*k), b%vol(i))
          end do
        else
          do i = share_first(b%np, comm%me, comm%nranks), &
            share_first(b%np, comm%me + 1, comm%nranks) - 1
            do j = 1, size(b%x, 1)
              call exact_add(a(2*k - 1), b%x(j, i))
            end do
            call exact_add(a(2*k), b%vol(i))
          end do
        end if
      end associate
    end do
    v = exact_allsum_many(a, comm)
    do k = 1, size(bodies)
      bodies(k)%fingerprint = v(2*k - 1:2*k)
    end do
  end subroutine body_fingerprints

  !> Is path a checkpoint that deck (with its bodies) can continue? Refused (exit 2): a
  !! file that is not an HDF5 file or not a checkpoint, a checkpoint of another format or
  !! mfcd version, one written by a different deck (its text differs) or with different
  !! bodies. Nothing is written. info: what the checkpoint says about itself.
  subroutine checkpoint_check(path, deck, bodies, info, err)
    character(len=*), intent(in) :: path
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(checkpoint_info_t), intent(out) :: info
    type(error_t), allocatable, intent(inout) :: err
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    call open_checked(path, deck, bodies, f, info, err)
    call h5_close(f, e2)
  end subroutine checkpoint_check

  !> Open checkpoint path and check it against deck and bodies (checkpoint_check); f stays
  !! open for reading when it passes.
  subroutine open_checked(path, deck, bodies, f, info, err)
    character(len=*), intent(in) :: path
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(h5file_t), intent(out) :: f
    type(checkpoint_info_t), intent(out) :: info
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: where, kind, version, text, orig, g
    character(len=*), parameter :: how = 'give the <stem>.checkpoint.h5 that a run of '// &
      'this deck wrote with &output checkpoint_every > 0'
    integer :: fmt, k, np
    real(wp) :: fp(2)
    where = "--restart '"//path//"': "
    info%git = ''
    if (deck%run%mode /= 'dynamic') then
      call set_error(err, where//"deck '"//deck%path//"' has mode = '"// &
        trim(deck%run%mode)//"'; only a dynamic run can be restarted")
      return
    end if
    call h5_open_read(f, path, err)
    if (allocated(err)) then
      err%message = where//err%message//"; "//how
      return
    end if
    if (h5_has_attr(f, '/', 'format')) call h5_read_attr(f, '/', 'format', kind, err)
    if (.not. allocated(kind)) kind = ''
    if (allocated(err) .or. trim(kind) /= checkpoint_kind) then
      call set_error(err, where//"not an mfcd checkpoint (no root attribute format = '"// &
        checkpoint_kind//"'; an mfcd output file is not a checkpoint); "//how)
      return
    end if
    call h5_read_attr(f, '/', 'format_version', fmt, err)
    if (.not. allocated(err)) call h5_read_attr(f, '/', 'code_version', version, err)
    if (.not. allocated(err)) call h5_read_attr(f, '/', 'git_commit', info%git, err)
    if (.not. allocated(err)) call h5_read_attr(f, '/', 'step', info%step, err)
    if (.not. allocated(err)) call h5_read_attr(f, '/', 'time', info%time, err)
    if (.not. allocated(err)) call h5_read_attr(f, '/', 'threads', info%threads, err)
    if (allocated(err)) then
      err%message = where//"a damaged checkpoint: "//err%message
      return
    end if
    if (fmt /= checkpoint_format) then
      call set_error(err, where//"checkpoint format "//itoa(fmt)//", written by mfcd "// &
        trim(version)//"; this mfcd ("//code_version//") reads format "// &
        itoa(checkpoint_format)//": continue it with the mfcd that wrote it, or start a "// &
        "new run")
      return
    end if
    if (trim(version) /= code_version) then
      call set_error(err, where//"written by mfcd "//trim(version)//" (git "// &
        trim(info%git)//"); this is mfcd "//code_version//" (git "//git_commit//"), and a "// &
        "continuation is exact only with the version that wrote it: restart with mfcd "// &
        trim(version)//", or start a new run")
      return
    end if
    call h5_read_text(f, '/deck', text, err)
    if (.not. allocated(err)) call h5_read_attr(f, '/', 'deck_path', orig, err)
    if (allocated(err)) then
      err%message = where//"a damaged checkpoint: "//err%message
      return
    end if
    if (text /= deck%text .or. len(text) /= len(deck%text)) then
      call set_error(err, where//"the checkpoint was written by a different deck: its "// &
        "deck text (/deck in the checkpoint, from '"//trim(orig)//"') differs from deck '"// &
        deck%path//"' "//first_difference(text, deck%text)//"; restart with the deck that "// &
        "wrote the checkpoint, unchanged, or start a new run")
      return
    end if
    do k = 1, size(bodies)
      g = '/bodies/'//trim(bodies(k)%name)
      np = -1
      fp = 0.0_wp
      if (h5_has_attr(f, g, 'np')) call h5_read_attr(f, g, 'np', np, err)
      if (h5_has_attr(f, g, 'sum_x_vol')) call h5_read_attr(f, g, 'sum_x_vol', fp, err)
      if (allocated(err)) deallocate(err)
      if (np /= bodies(k)%np .or. any(fp /= bodies(k)%fingerprint)) then
        call set_error(err, where//"the checkpoint was written with different particles "// &
          "of body '"//trim(bodies(k)%name)//"' ("//itoa(np)//" particles there, "// &
          itoa(bodies(k)%np)//" here, or other positions or volumes) under the same deck "// &
          "text: was a particle file (&body file) changed? Restart with the bodies that "// &
          "wrote it, or start a new run")
        return
      end if
    end do
  end subroutine open_checked

  !> 'at line L: 'a' against 'b'': the first line where texts a (checkpoint) and b (deck)
  !! differ.
  function first_difference(a, b) result(s)
    character(len=*), intent(in) :: a, b
    character(len=:), allocatable :: s
    integer :: ia, ib, ja, jb, line
    ia = 1
    ib = 1
    line = 1
    do
      ja = line_end(a, ia)
      jb = line_end(b, ib)
      if (ia > len(a) .or. ib > len(b)) exit
      if (a(ia:ja) /= b(ib:jb) .or. (ja - ia) /= (jb - ib)) exit
      ia = ja + 2
      ib = jb + 2
      line = line + 1
    end do
    s = 'at line '//itoa(line)//": '"//clip(a, ia, ja)//"' in the checkpoint, '"// &
      clip(b, ib, jb)//"' in the deck"
  contains
    pure integer function line_end(t, i) result(j)
      character(len=*), intent(in) :: t
      integer, intent(in) :: i
      j = len(t)
      if (i > len(t)) return
      j = index(t(i:), new_line('a'))
      if (j == 0) then
        j = len(t)
      else
        j = i + j - 2
      end if
    end function line_end
    function clip(t, i, j) result(c)
      character(len=*), intent(in) :: t
      integer, intent(in) :: i, j
      character(len=:), allocatable :: c
      if (i > len(t)) then
        c = '(end of text)'
      else
        c = trim(t(i:min(j, i + 79)))
      end if
    end function clip
  end function first_difference

  !> Load the checkpoint at path into a run set up from deck and bodies (solids, pairs and
  !! the record as set-up leaves them): the record, every solid's state and the pairs'
  !! counters are overwritten; hist gets every history row so far, nsnap_done and
  !! snap_times the deck snapshots already written. Refused as checkpoint_check refuses,
  !! and when the stored arrays do not fit the solids (exit 2); nothing is written.
  subroutine checkpoint_read(path, deck, bodies, r, solids, pairs, hist, nsnap_done, &
    snap_times, err, fields)
    character(len=*), intent(in) :: path
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(run_record_t), intent(inout) :: r
    type(solid_t), intent(inout) :: solids(:)
    type(contact_pair_t), intent(inout) :: pairs(:)
    type(history_t), intent(out) :: hist
    integer, intent(out) :: nsnap_done
    real(wp), allocatable, intent(out) :: snap_times(:)
    type(error_t), allocatable, intent(inout) :: err
    !> .false.: the solids' scalars only, not their state fields (MPI ranks read the rows
    !! of their parts after the split: checkpoint_read_part)
    logical, intent(in), optional :: fields
    type(h5file_t) :: f
    type(checkpoint_info_t) :: info
    type(error_t), allocatable :: e2
    integer, allocatable :: dims(:)
    integer(i64) :: counts(4), more(7), nskip(1)
    real(wp) :: bgap(2), tdet(1), travel(1), tpair(1)
    integer(i64) :: limbs(exact_pack_size)
    integer :: k, ncol
    logical :: has
    nsnap_done = 0
    allocate(snap_times(0))
    call open_checked(path, deck, bodies, f, info, err)
    if (allocated(err)) then
      call h5_close(f, e2)
      return
    end if
    call read_record(f, r, err)
    do k = 1, size(solids)
      if (.not. allocated(err)) call read_solid(f, solids(k), err, fields)
    end do
    do k = 1, size(pairs)
      if (allocated(err)) exit
      call h5_read(f, '/contacts/contact'//itoa(k), counts, err)
      pairs(k)%count%screened = counts(1)
      pairs(k)%count%evaluated = counts(2)
      pairs(k)%count%detected = counts(3)
      pairs(k)%count%contacts = counts(4)
      ! skip_far's state (absent from checkpoints written before it: every particle is then
      ! screened at the first step, which changes the counter only)
      associate (s => pairs(k)%side(1))
        has = .false.
        if (s%skip_far) has = h5_has(f, '/contacts/contact'//itoa(k)//'_skip_due')
        if (has) then
          call h5_read(f, '/contacts/contact'//itoa(k)//'_skipped', nskip, err)
          if (.not. allocated(err)) call h5_read(f, '/contacts/contact'//itoa(k)// &
            '_skip_travel', travel, err)
          if (allocated(s%glob)) then
            ! (a rank's region of the slave: its rows only)
            call read_side_rows(f, '/contacts/contact'//itoa(k), pairs(k), err)
          else
            if (.not. allocated(err)) call h5_read(f, '/contacts/contact'//itoa(k)// &
              '_skip_due', s%due, err)
            if (.not. allocated(err)) call h5_read(f, '/contacts/contact'//itoa(k)// &
              '_skip_d', s%d_scr, err)
          end if
          if (allocated(err)) exit
          pairs(k)%count%skipped = nskip(1)
          s%travel = travel(1)
        end if
      end associate
      ! the detector comparison's counters (absent from checkpoints written before them)
      if (.not. h5_has(f, '/contacts/contact'//itoa(k)//'_compare')) cycle
      call h5_read(f, '/contacts/contact'//itoa(k)//'_compare', more, err)
      if (.not. allocated(err)) call h5_read(f, '/contacts/contact'//itoa(k)//'_buffer_gap', &
        bgap, err)
      if (.not. allocated(err)) call h5_read(f, '/contacts/contact'//itoa(k)// &
        '_detect_time', tdet, err)
      if (allocated(err)) exit
      associate (c => pairs(k)%count)
        c%detected_max = more(1)
        c%cmp_det = more(2)
        c%cmp_gap = more(3)
        c%cmp_buffer = more(4)
        c%cmp_missed = more(5)
        c%cmp_det_max = more(6)
        c%cmp_gap_max = more(7)
        c%buffer_gap_sum = bgap(1)
        ! (the exact sum; absent from checkpoints written before 2026-11-30: then continued
        ! from the rounded sum, and a mean's last bit may differ)
        c%buffer_gap_exact = exact_sum_t()
        if (h5_has(f, '/contacts/contact'//itoa(k)//'_buffer_gap_exact')) then
          call h5_read(f, '/contacts/contact'//itoa(k)//'_buffer_gap_exact', limbs, err)
          if (.not. allocated(err)) c%buffer_gap_exact = exact_unpack(limbs)
        else
          call exact_add(c%buffer_gap_exact, bgap(1))
        end if
        c%buffer_gap_max = bgap(2)
        c%t_detect = tdet(1)
      end associate
      ! the pair's wall time (absent from checkpoints written before it)
      if (h5_has(f, '/contacts/contact'//itoa(k)//'_pair_time')) then
        call h5_read(f, '/contacts/contact'//itoa(k)//'_pair_time', tpair, err)
        if (.not. allocated(err)) pairs(k)%count%t_pair = tpair(1)
      end if
      ! its friction work (absent from checkpoints written before it)
      if (h5_has(f, '/contacts/contact'//itoa(k)//'_w_friction')) then
        call h5_read(f, '/contacts/contact'//itoa(k)//'_w_friction', tpair, err)
        if (.not. allocated(err)) then
          pairs(k)%count%w_friction = tpair(1)
          ! its exact sum (absent from checkpoints written before it: then the value)
          pairs(k)%count%w_friction_sum = exact_sum_t()
          if (h5_has(f, '/contacts/contact'//itoa(k)//'_w_friction_exact')) then
            call h5_read(f, '/contacts/contact'//itoa(k)//'_w_friction_exact', limbs, err)
            if (.not. allocated(err)) pairs(k)%count%w_friction_sum = exact_unpack(limbs)
          else
            call exact_add(pairs(k)%count%w_friction_sum, tpair(1))
          end if
        end if
      end if
      ! 3D self-contact's flags of a sign not sure (absent from checkpoints before it)
      if (h5_has(f, '/contacts/contact'//itoa(k)//'_self_unsure')) then
        call h5_read(f, '/contacts/contact'//itoa(k)//'_self_unsure', nskip, err)
        if (.not. allocated(err)) pairs(k)%count%self_unsure = nskip(1)
      end if
    end do
    if (.not. allocated(err)) call h5_read_attr(f, '/output', 'nsnap_done', nsnap_done, err)
    if (.not. allocated(err)) call h5_shape(f, '/output/snapshot_times', dims, err)
    if (.not. allocated(err)) then
      deallocate(snap_times)
      allocate(snap_times(dims(1)))
      call h5_read(f, '/output/snapshot_times', snap_times, err)
    end if
    if (.not. allocated(err)) call h5_shape(f, '/output/history', dims, err)
    if (.not. allocated(err)) then
      ! the run's columns and those of each deformable body (history_create)
      ncol = history_width(count(deck%bodies(1:deck%nbodies)%role /= 'rigid'), &
        deck%ncontacts, deck%nbcs, history_geometry(deck%run%ndim, &
        deck%run%geometry == 'axisymmetric'))
      if (dims(1) /= ncol) call set_error(err, 'its history rows have '//itoa(dims(1))// &
        ' columns, this run writes '//itoa(ncol)//' (a checkpoint of an mfcd before '// &
        'the per-body and per-pair history?): run the deck from t = 0')
    end if
    if (.not. allocated(err)) then
      allocate(hist%rows(dims(1), max(dims(2), 1024)))
      hist%n = dims(2)
      call h5_read(f, '/output/history', hist%rows(:, 1:hist%n), err)
    end if
    call h5_close(f, e2)
    if (allocated(err)) then
      err%message = "--restart '"//path//"': the checkpoint does not fit the run set up "// &
        "from deck '"//deck%path//"': "//err%message
      return
    end if
    call log_print("restart: from checkpoint '"//path//"' at step "//itoa(info%step)// &
      ", t = "//rtoa(info%time)//" s (written with "//itoa(info%threads)//" thread(s), git "// &
      trim(info%git)//")")
    if (info%threads /= omp_get_max_threads()) call log_print('restart: note: this run '// &
      'has '//itoa(omp_get_max_threads())//' thread(s); sums over threads (energies, '// &
      'contact force) then differ in round-off from an uninterrupted run')
    if (trim(info%git) /= git_commit) call log_print('restart: note: written by git '// &
      trim(info%git)//', this is git '//git_commit//': the continuation is exact only '// &
      'when the code that computes a step is the same')
  end subroutine checkpoint_read

  subroutine read_record(f, r, err)
    type(h5file_t), intent(in) :: f
    type(run_record_t), intent(inout) :: r
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: g = '/record'
    integer(i64) :: counts(2), sc(5)
    integer :: flag
    real(wp) :: wall, v4(4), v3(3)
    call h5_read_attr(f, g, 'n', r%n, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 't', r%t, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'dt', r%dt, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'nsteps_est', r%nsteps_est, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'energy_over', r%energy_over, err)
    if (.not. allocated(err)) call h5_read(f, g//'/node_point_steps', counts, err)
    r%node_steps = counts(1)
    r%point_steps = counts(2)
    if (.not. allocated(err)) call h5_read(f, g//'/subcycle_counts', sc, err)
    r%sub%steps = sc(1)
    r%sub%substeps = sc(2)
    r%sub%fine_evals = sc(3)
    r%sub%uniform_evals = sc(4)
    r%sub%m_max = int(sc(5))
    if (.not. allocated(err)) call h5_read_attr(f, g, 'wall', wall, err)
    ! the wall clock goes on from the time already spent
    r%wall0 = omp_get_wtime() - wall
    if (.not. allocated(err)) call h5_read_attr(f, g, 't_loop', r%t_loop, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 't_contact', r%t_contact, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 't_output', r%t_output, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'pen_max', r%pen_max, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'impulse', r%impulse, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 't_edge_first', r%t_edge_first, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 't_edge_sep', r%t_edge_sep, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'edge_prev', flag, err)
    r%edge_prev = flag == 1
    if (.not. allocated(err)) call h5_read_attr(f, g, 'contact_n', r%contact%n_contact, err)
    v4 = 0.0_wp
    if (.not. allocated(err)) call h5_read_attr(f, g, 'contact_force_radius_pen', v4, err)
    r%contact%force_normal = v4(1)
    r%contact%radius = v4(2)
    r%contact%pen_before = v4(3)
    r%contact%pen_after = v4(4)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'contact_edge', flag, err)
    r%contact%edge_in_contact = flag == 1
    associate (c => r%step)
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_adaptive', flag, err)
      c%adaptive = flag == 1
      v3 = 0.0_wp
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_cfl_fixed_dtc0', v3, err)
      c%cfl = v3(1)
      c%dt_fixed = v3(2)
      c%dtc0 = v3(3)
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_dtc', c%dtc, err)
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_solid', c%solid, err)
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_point', c%point, err)
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_solid_min', c%solid_min, err)
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_point_min', c%point_min, err)
      v3 = 0.0_wp
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_dt_min_max_t', v3, err)
      c%dt_min = v3(1)
      c%dt_max = v3(2)
      c%t_dt_min = v3(3)
      ! (absent from checkpoints written before it: the steps since are still counted)
      if (.not. allocated(err)) then
        if (h5_has_attr(f, g, 'step_dt_min_taken')) then
          call h5_read_attr(f, g, 'step_dt_min_taken', v3(1:2), err)
          c%dt_min_taken = v3(1)
          c%t_dt_min_taken = v3(2)
        end if
      end if
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_dtc_min', c%dtc_min, err)
      if (.not. allocated(err)) call h5_read_attr(f, g, 'step_n_over', c%n_over, err)
    end associate
    r%failed = .false.
    r%reason = ''
  end subroutine read_record

  subroutine read_solid(f, s, err, fields)
    type(h5file_t), intent(in) :: f
    type(solid_t), intent(inout) :: s
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: fields
    character(len=:), allocatable :: g
    real(wp) :: en(8), kd(2)
    integer :: k
    logical :: with_fields
    with_fields = .true.
    if (present(fields)) with_fields = fields
    g = '/solids/'//trim(s%name)
    if (.not. h5_has(f, g)) then
      call set_error(err, "no state of body '"//trim(s%name)//"' (/solids/"// &
        trim(s%name)//")")
      return
    end if
    do k = 1, size(state_fields)
      if (allocated(err) .or. .not. with_fields) exit
      call read_field(f, g, s, k, err)
    end do
    if (allocated(err)) return
    if (.not. allocated(err)) call h5_read_attr(f, g, 'contact_impulse_time', &
      s%state%ipoint_time, err)
    en = 0.0_wp
    kd = 0.0_wp
    if (.not. allocated(err)) call h5_read_attr(f, g, 'energies', en, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'kappa_dt_cal', kd, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'kappa_q', s%kappa_q, err)
    if (.not. allocated(err)) call h5_read_attr(f, g, 'wall', s%acc%wall, err)
    if (allocated(err)) return
    call solid_set_energies(s, en)
    s%kappa = kd(1)
    s%dt_cal = kd(2)
    if (.not. with_fields) return
    call solid_state_derived(s)
    if (s%quiet_on .and. .not. allocated(err)) call read_quiet(f, g, s, err)
  end subroutine read_solid

  !> skip_far's state of pair p's slave side when it holds a rank's region of the body
  !! (contact_pair_m side_t glob), from the datasets c_skip_due and c_skip_d: the
  !! region's rows.
  subroutine read_side_rows(f, c, p, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: c
    type(contact_pair_t), intent(inout) :: p
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: due(:, :)
    associate (s => p%side(1))
      allocate(due(1, s%np))
      call h5_read_rows(f, c//'_skip_due', due, s%glob, s%np_whole, .true., err)
      if (.not. allocated(err)) s%due = due(1, :)
      if (.not. allocated(err)) call h5_read_rows(f, c//'_skip_d', s%d_scr, s%glob, &
        s%np_whole, size(s%d_scr, 1) == 1, err)
    end associate
  end subroutine read_side_rows

  !> The state fields of solid p, a rank's part, from the checkpoint at path (checked
  !! already by checkpoint_read, which read the scalars): the rows of its local nodes and
  !! points, ghosts too (the exchanges need not run before the first step), by their
  !! global numbers; no rank reads the whole state.
  subroutine checkpoint_read_part(path, p, err)
    character(len=*), intent(in) :: path
    type(solid_t), intent(inout) :: p
    type(error_t), allocatable, intent(inout) :: err
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    real(wp), allocatable :: buf(:, :)
    integer :: k, rows, j
    character(len=:), allocatable :: g
    call h5_open_read(f, path, err)
    if (allocated(err)) return
    g = '/solids/'//trim(p%name)//'/'
    do k = 1, size(state_fields)
      if (.not. field_in(f, g, k)) cycle
      associate (fk => state_fields(k))
        rows = solid_field_rows(p, k)
        if (fk%nodal) then
          allocate(buf(rows, size(p%part%nglob)))
          call h5_read_rows(f, g//trim(fk%name), buf, p%part%nglob, p%part%np_whole, &
            rows == 1, err)
        else
          allocate(buf(rows, size(p%part%qglob)))
          call h5_read_rows(f, g//trim(fk%name), buf, p%part%qglob, p%part%nq_whole, &
            rows == 1, err)
        end if
        if (.not. allocated(err)) call solid_put_field(p, k, buf, [(j, j = 1, size(buf, 2))])
        deallocate(buf)
      end associate
      if (allocated(err)) exit
    end do
    call h5_close(f, e2)
    if (allocated(err)) then
      err%message = "--restart '"//path//"': "//err%message
      return
    end if
    call solid_state_derived(p)
  end subroutine checkpoint_read_part

  !> Whether group g (ending in '/') of a checkpoint holds state field k: every field
  !! but 'estab' must (checkpoints before 2026-11-30 have none: the points' stabilization
  !! energies are then zero until the next force evaluation, which a run that goes on
  !! makes at its first step).
  logical function field_in(f, g, k) result(yes)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: g
    integer, intent(in) :: k
    yes = .true.
    if (state_fields(k)%name == 'estab') yes = h5_has(f, g//trim(state_fields(k)%name))
  end function field_in

  !> State field k (state_fields) of solid s from dataset g/<name> (write_field's shape).
  subroutine read_field(f, g, s, k, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: g
    type(solid_t), intent(inout) :: s
    integer, intent(in) :: k
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: buf(:, :), row(:)
    integer :: rows, n, i
    rows = solid_field_rows(s, k)
    n = merge(s%np, s%nq, state_fields(k)%nodal)
    if (.not. field_in(f, g//'/', k)) return
    allocate(buf(rows, n))
    if (rows == 1) then
      allocate(row(n))
      call h5_read(f, g//'/'//trim(state_fields(k)%name), row, err)
      if (allocated(err)) return
      buf(1, :) = row
    else
      call h5_read(f, g//'/'//trim(state_fields(k)%name), buf, err)
      if (allocated(err)) return
    end if
    call solid_put_field(s, k, buf, [(i, i = 1, n)])
  end subroutine read_field

  !> The quiet-point state of solid s from group g (checkpoints written before it have
  !! none: every point is then active, which changes round-off only).
  subroutine read_quiet(f, g, s, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: g
    type(solid_t), intent(inout) :: s
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: flags(2)
    real(wp), allocatable :: aw(:), qa(:)
    if (.not. h5_has(f, g//'/quiet_awake')) then
      s%all_awake = .true.
      s%awake = .true.
      s%qact = .true.
      return
    end if
    allocate(aw(s%np), qa(s%nq))
    call h5_read_attr(f, g, 'quiet_all_awake_skipped', flags, err)
    if (.not. allocated(err)) call h5_read(f, g//'/quiet_awake', aw, err)
    if (.not. allocated(err)) call h5_read(f, g//'/quiet_active', qa, err)
    if (allocated(err)) return
    s%all_awake = flags(1) > 0.5_wp
    s%acc%quiet_skipped = nint(flags(2), i64)
    s%awake = aw > 0.5_wp
    s%qact = qa > 0.5_wp
    call solid_quiet_blocks(s)
  end subroutine read_quiet
end module run_checkpoint_m
