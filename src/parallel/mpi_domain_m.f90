!> A dynamic run on MPI ranks (doc/parallel.md): the run_domain_t of the one driver
!! (explicit_driver_m) for the ranks of an MPI communicator. The driver's loop is the serial
!! one; this is what differs on ranks.
!!
!! Every rank builds the set-up (bodies, solids, contact pairs: as a serial run, but for a
!! 3D RKPM solid the ranks other than 0 keep only the table rows of their region:
!! dynamic_setup_m's setup_part_t), then split keeps its part of each solid
!! (decomposition_m: recursive coordinate bisection of the reference configuration) with
!! its halo (halo_m, as the part's part_halo_t: the part exchanges its ghosts inside
!! solid_internal_force, solid_update and contact itself), frees the whole solids on the
!! ranks other than 0, and
!! narrows each contact pair to it: against a rigid master each rank holds the master whole;
!! against a deforming master (self-contact too) each rank its own and ghost master
!! particles (contact_dist_sm). Nodal values are the serial ones to the bit for any number of
!! ranks; energies and the contact force are sums of per-rank sums (round-off); kappa is a
!! maximum (exact), and the critical step at t = 0 is calibrated on the parts with exact
!! sums (stable_step_m): the step is the serial one to the bit.
!!
!! Rank 0 writes the one HDF5 file (and XDMF) a serial run writes: for a snapshot, a failure,
!! a checkpoint and the summary it gathers the whole solids (the parts' owned values), and
!! draws the snapshots' det(M) fields from them with its copy of the pairs as set up. A
!! history row's measures are maxima over the ranks, without a gather. Checkpoints are the
!! serial ones, written by rank 0 from the gathered state and read whole by every rank, so a
!! run continues on any number of ranks. Subcycling is refused (dynamic_setup_m's
!! mpi_scene_check).
module mpi_domain_m
  use mpi_f08
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use body_m, only: body_t
  use run_output_m, only: write_body_rows
  use solid_m, only: solid_t, solid_init, solid_set_owned, part_halo_t, state_fields, &
    solid_field_rows, solid_get_field, solid_put_field, solid_state_derived, &
    solid_energies, solid_set_energies, solid_set_gravity, solid_state_t, solid_sub_t, &
    solid_account_sums, solid_np_whole, solid_nq_whole
  use decomposition_m, only: rcb_tree_t, rcb_build_ranks, rcb_part, local_part_t, &
    local_part_sets, local_part_rows
  use solid_tables_m, only: solid_tables_t, tables_copy_scalars, tables_transpose
  use halo_m, only: halo_plan_t, halo_plan_build, halo_nodes, halo_points
  use rank_comm_m, only: rank_comm_t, share_first
  use exact_sum_m, only: exact_sum_t, exact_add, exact_value, exact_allmerge, exact_allsum_many
  use mpi_comm_m, only: mpi_ranks_t, mpi_ranks_init
  use contact_pair_m, only: contact_pair_t, contact_stats_t, stat_sums, stats_values, &
    contact_pair_localize, contact_pair_cut, contact_pair_distribute, contact_pair_own, &
    contact_dist_report
  use contact_m, only: contact_counters_t
  use body_measures_m, only: measures_t, body_measures_part
  use run_report_m, only: run_record_t, self_det_out
  use run_files_m, only: run_files_t, run_files_checkpoint, run_files_checkpoint_commit, &
    run_files_checkpoint_failed
  use run_checkpoint_m, only: checkpoint_write_fields, checkpoint_read_part
  use hdf5_io_m, only: h5file_t, h5_open_rw, h5_close
  use dynamic_output_m, only: snapshot_write
  use mpi_output_m, only: h5_open_collective, h5_close_collective
  use run_domain_m, only: run_domain_t
  implicit none
  private
  public :: mpi_domain_t, mpi_domain_init, ghost_margin_default

  !> The default margin of the ghost width of contact with a deforming master, a fraction of
  !! the width contact needs: larger, fewer refreshes and more ghosts (doc/parallel.md)
  real(wp), parameter :: ghost_margin_default = 0.5_wp

  !> A part's exchanges with its neighbour ranks (halo_m), as its solid calls them.
  type, extends(part_halo_t) :: mpi_halo_t
    type(halo_plan_t) :: plan
    real(wp), allocatable :: w(:, :)   !< (2 ndim, local nodes): two nodal arrays in one message
  contains
    procedure :: nodes => halo_node_array
    procedure :: nodes2 => halo_node_pair
    procedure :: points => halo_point_array
  end type mpi_halo_t

  !> The ranks of an MPI communicator: each solid's part, its halo and the whole solids.
  type, extends(run_domain_t) :: mpi_domain_t
    type(MPI_Comm) :: mcomm
    type(mpi_ranks_t) :: ranks
    real(wp) :: ghost_margin = ghost_margin_default
    logical :: ghost_refresh = .true.
    !> rank 0 keeps the whole solids after the split (its det(M) fields draw on them);
    !! else every rank keeps only its part and the whole solids' sizes
    logical :: root_whole = .true.
    !> the whole solids: rank 0's for output; on the other ranks their sizes only, after
    !! the split (and their tables, for a 3D RKPM solid, the rows of the rank's region)
    type(solid_t), allocatable :: gs(:)
    type(local_part_t), allocatable :: lp(:)      !< each solid's part
    type(mpi_halo_t), allocatable :: halos(:)     !< each part's halo (its solid points here)
    type(contact_pair_t), allocatable :: pairs_whole(:)   !< rank 0: the pairs as set up
    integer(i64), allocatable :: flag_max(:)      !< each pair's most flagged in one step
    !> each pair's most flagged in one step by det(M) and by the gap (compare_detectors)
    integer(i64), allocatable :: cmp_max(:, :)
  contains
    procedure :: split => mpi_split
    procedure :: whole => mpi_whole
    procedure :: output_pairs => mpi_pairs
    procedure :: whole_nodes => mpi_nodes
    procedure :: whole_points => mpi_points
    procedure :: measures => mpi_measures
    procedure :: contact_stats => mpi_stats
    procedure :: counters => mpi_counters
    procedure :: checkpoint => mpi_checkpoint
    procedure :: snapshot_solids => mpi_snapshot
    procedure :: bodies_rows => mpi_bodies_rows
    procedure :: finish => mpi_finish
  end type mpi_domain_t

contains

  !> The domain of the ranks of comm (dom must stay where it is: the solids' halos and the
  !! communicator point into it). ghost_margin: the margin of the ghost width of contact
  !! with a deforming master, a fraction of the width contact needs; ghost_refresh
  !! .false.: testing only, the first ghost sets are kept (contacts they miss are missed).
  subroutine mpi_domain_init(dom, comm, ghost_margin, ghost_refresh, root_whole)
    type(mpi_domain_t), intent(inout), target :: dom
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: ghost_margin
    logical, intent(in) :: ghost_refresh
    !> rank 0 keeps the whole solids after the split (for its det(M) fields; default)
    logical, intent(in), optional :: root_whole
    dom%mcomm = comm
    call mpi_ranks_init(dom%ranks, comm)
    dom%comm => dom%ranks
    dom%root = dom%ranks%me == 0
    dom%ghost_margin = ghost_margin
    dom%ghost_refresh = ghost_refresh
    dom%root_whole = .true.
    if (present(root_whole)) dom%root_whole = root_whole
    dom%reads_parts = .true.
  end subroutine mpi_domain_init

  !> solids (the whole set-up, and with restarted the state a checkpoint held) become this
  !! rank's parts; the whole ones are kept for output; the pairs are narrowed to the parts.
  subroutine mpi_split(dom, solids, pairs, restarted, trees, err)
    class(mpi_domain_t), intent(inout), target :: dom
    type(solid_t), allocatable, intent(inout), target :: solids(:)
    type(contact_pair_t), intent(inout) :: pairs(:)
    logical, intent(in) :: restarted
    type(rcb_tree_t), intent(in) :: trees(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, nk
    class(rank_comm_t), pointer :: comm_ptr
    ! every rank read the whole state; rank 0 keeps the pairs' counters (sums)
    dom%flag_max = [(pairs(k)%count%detected_max, k = 1, size(pairs))]
    allocate(dom%cmp_max(2, size(pairs)))
    do k = 1, size(pairs)
      dom%cmp_max(:, k) = [pairs(k)%count%cmp_det_max, pairs(k)%count%cmp_gap_max]
    end do
    if (.not. dom%root) then
      do k = 1, size(pairs)
        pairs(k)%count = contact_counters_t()
      end do
    end if
    nk = size(solids)
    call move_alloc(solids, dom%gs)
    ! (the whole solids' state freed first where they are released after the split)
    if (.not. keeps_whole(dom)) then
      do k = 1, nk
        call strip_whole(dom%gs(k))
      end do
    end if
    allocate(solids(nk), dom%lp(nk), dom%halos(nk))
    ! rank 0's copy of the pairs as set up on the whole bodies, for the det(M) output of
    ! the snapshots (drawn from the gathered state: contact_det_fields); before make_part
    ! cuts the slave sides against rigid masters
    if (keeps_whole(dom)) allocate(dom%pairs_whole, source=pairs)
    do k = 1, nk
      call make_part(dom, k, trees(k), solids(k), pairs, err)
      if (dom%any_error(err)) return
      ! (the halo first: a restart's averaged nodal pressure takes the ghosts' J through it)
      solids(k)%part%halo => dom%halos(k)
      if (restarted) call restart_part(dom, k, solids(k), err)
      if (dom%any_error(err)) return
    end do
    comm_ptr => dom%ranks
    do k = 1, size(pairs)
      associate (s1 => pairs(k)%side(1)%isolid, s2 => pairs(k)%side(2)%isolid)
        if (s2 == 0) then
          call contact_pair_localize(pairs(k), dom%lp(s1)%nglob, solids, comm_ptr, err)
        else
          ! a deforming master: each rank its own slave particles against its own and
          ! ghost master particles, and the other way round (contact_dist_sm)
          call contact_pair_distribute(pairs(k), solids, comm_ptr, &
            dom%lp(s1)%nglob, dom%lp(s2)%nglob, dom%ghost_margin, &
            dom%ghost_refresh, err)
        end if
      end associate
      if (dom%any_error(err)) return
    end do
    ! only rank 0 draws on the whole solids (the det(M) output), if at all; the others keep
    ! their sizes only
    if (.not. keeps_whole(dom)) then
      do k = 1, nk
        call release_whole(dom%gs(k))
      end do
    end if
  end subroutine mpi_split

  !> The whole solid g reduced to what make_part and restart_part read of it (reference
  !! positions, kinematic conditions, velocities, tables, material, scalars): its state and
  !! work arrays over all its nodes and points are freed before the parts are made, so that
  !! the split's peak holds them for the parts only.
  subroutine strip_whole(g)
    type(solid_t), intent(inout) :: g
    real(wp), allocatable :: v(:, :)
    real(wp) :: ipoint_time
    call move_alloc(g%state%v, v)
    ipoint_time = g%state%ipoint_time
    g%state = solid_state_t()
    call move_alloc(v, g%state%v)
    g%state%ipoint_time = ipoint_time
    g%sub = solid_sub_t()
    if (allocated(g%fint)) deallocate(g%fint)
    if (allocated(g%fext)) deallocate(g%fext)
    if (allocated(g%fcon)) deallocate(g%fcon)
    if (allocated(g%fpoint)) deallocate(g%fpoint)
    if (allocated(g%x)) deallocate(g%x)
    if (allocated(g%dr)) deallocate(g%dr)
    if (allocated(g%spin)) deallocate(g%spin)
    if (allocated(g%dwp)) deallocate(g%dwp)
    if (allocated(g%stab)) deallocate(g%stab)
    if (allocated(g%jq)) deallocate(g%jq)
    if (allocated(g%jn)) deallocate(g%jn)
    if (allocated(g%fbar)) deallocate(g%fbar)
    if (allocated(g%fbar_old)) deallocate(g%fbar_old)
    if (allocated(g%taup)) deallocate(g%taup)
    if (allocated(g%kap0)) deallocate(g%kap0)
    if (allocated(g%awake)) deallocate(g%awake)
    if (allocated(g%qact)) deallocate(g%qact)
    if (allocated(g%bact)) deallocate(g%bact)
  end subroutine strip_whole

  !> Whether this rank keeps the whole solids after the split (rank 0, for det(M) fields
  !! drawn from them); every other rank frees them but for their sizes.
  pure logical function keeps_whole(dom)
    type(mpi_domain_t), intent(in) :: dom
    keeps_whole = dom%root .and. dom%root_whole
  end function keeps_whole

  !> The whole solid g reduced to its name, sizes and the scalars of its tables (what the
  !! XDMF file and the summary say of it; the arrays freed).
  subroutine release_whole(g)
    type(solid_t), intent(inout) :: g
    type(solid_t) :: shell
    shell%name = g%name
    ! (a region shell's whole counts: what the output says of the whole solid)
    shell%np = solid_np_whole(g)
    shell%nq = solid_nq_whole(g)
    call tables_copy_scalars(g%t, shell%t)
    shell%t%np = shell%np
    shell%t%nq = shell%nq
    g = shell
  end subroutine release_whole

  !> Solid k's part on this rank: the bisection of the whole solid's nodes and points by
  !! set_tree (the set-up's, whose boxes its region was built for; on one rank, where the
  !! set-up made none, made here), the part's tables, its halo plan, the part solid (its
  !! velocities, kinetic energy at t = 0 of its own nodes, limits and stabilization as the
  !! whole solid's); the contact sides on it cut to the part before its rows are made.
  subroutine make_part(dom, k, set_tree, p, pairs, err)
    type(mpi_domain_t), intent(inout), target :: dom
    integer, intent(in) :: k
    type(rcb_tree_t), intent(in) :: set_tree
    type(solid_t), intent(out) :: p
    type(contact_pair_t), intent(inout) :: pairs(:)
    type(error_t), allocatable, intent(inout) :: err
    type(rcb_tree_t) :: tree
    integer, allocatable :: node_part(:), point_part(:), bc_of(:, :), ow(:), vo(:)
    real(wp), allocatable :: x0(:, :), vpres(:, :), v(:, :)
    logical, allocatable :: pres(:, :)
    integer :: i, q, j, sd
    associate (g => dom%gs(k), lp => dom%lp(k), h => dom%halos(k))
      associate (r => dom%ranks%me, nr => dom%ranks%nranks)
        if (allocated(set_tree%part) .and. set_tree%nparts == nr) then
          tree = set_tree
        else
          ! (each rank gives its share of the nodes: rcb_build's tree)
          call rcb_build_ranks(g%x0(:, share_first(g%np, r, nr):share_first(g%np, r + 1, &
            nr) - 1), nr, dom%ranks, tree)
        end if
      end associate
      ! (a region shell's nodes and points: the region's, numbered over it; lp's sets
      ! are places in it until its rows are made, then the whole solid's numbers)
      allocate(node_part(g%np), point_part(g%nq))
      do i = 1, g%np
        node_part(i) = rcb_part(tree, g%x0(:, i))
      end do
      do q = 1, g%nq
        point_part(q) = rcb_part(tree, g%t%xq(:, q))
      end do
      call local_part_sets(g%t, node_part, point_part, dom%ranks%me + 1, lp)
      ! the slave sides of this solid against rigid masters (arrays over the whole solid)
      ! cut to the part before its rows are made: gone before the split's peak
      ! (contact_pair_localize does the rest once the part solid exists)
      do j = 1, size(pairs)
        if (pairs(j)%side(1)%isolid /= k .or. pairs(j)%side(2)%isolid /= 0) cycle
        if (g%part%region) then
          call contact_pair_cut(pairs(j), g%part%nglob(lp%nglob), err)
        else
          call contact_pair_cut(pairs(j), lp%nglob, err)
        end if
        if (allocated(err)) return
      end do
      ! so are the sides of this solid in a pair whose master deforms (or a self-contact)
      ! (their ghosts come once the parts exist: contact_pair_distribute); their particles'
      ! and their whole surfaces' vertices' ranks from the bisection at their reference
      ! positions (the nodes' own: node_part)
      do j = 1, size(pairs)
        if (pairs(j)%side(2)%isolid == 0) cycle
        do sd = 1, 2
          associate (s => pairs(j)%side(sd))
            if (s%isolid /= k) cycle
            allocate(ow(s%np))
            do i = 1, s%np
              ow(i) = rcb_part(tree, s%x_ref(:, i)) - 1
            end do
            if (s%ndim == 3) then
              allocate(vo(size(s%surf3%vid)))
              do i = 1, size(vo)
                vo(i) = rcb_part(tree, s%surf3%x(:, i)) - 1
              end do
            else
              allocate(vo(2*s%surface%nseg))
              do i = 1, s%surface%nseg
                vo(i) = rcb_part(tree, s%surface%a(:, i)) - 1
                vo(s%surface%nseg + i) = rcb_part(tree, s%surface%b(:, i)) - 1
              end do
            end if
          end associate
          call contact_pair_own(pairs(j), sd, ow, vo, dom%ranks%me, dom%ranks%nranks, err)
          deallocate(ow, vo)
          if (allocated(err)) return
        end do
      end do
      ! what the part solid takes of the whole solid's arrays over its nodes, taken now
      ! and the whole ones freed before the part's rows too (but on rank 0 when it keeps
      ! the whole solids)
      x0 = g%x0(:, lp%nglob)
      pres = g%pres(:, lp%nglob)
      vpres = g%vpres(:, lp%nglob)
      v = g%state%v(:, lp%nglob)
      if (allocated(g%bc_of)) bc_of = g%bc_of(:, lp%nglob)
      if (.not. keeps_whole(dom)) then
        deallocate(g%x0, g%pres, g%vpres, g%state%v)
        if (allocated(g%bc_of)) deallocate(g%bc_of)
      end if
      ! the whole solid's tables (the region's rows) are freed as the part's rows are
      ! copied, array by array, and before the part's transpose (but on rank 0 when its
      ! det(M) fields draw on them), so that the split's peak holds one set of rows, the
      ! part's, and its transpose
      call local_part_rows(g%t, lp, transpose=.false., release=.not. keeps_whole(dom))
      call tables_transpose(lp%t)
      node_part = node_part(lp%nglob)
      point_part = point_part(lp%qglob)
      if (g%part%region) then
        lp%nglob = g%part%nglob(lp%nglob)
        lp%qglob = g%part%qglob(lp%qglob)
        deallocate(g%part%nglob, g%part%qglob)
      end if
      call halo_plan_build(dom%mcomm, lp, node_part, point_part, h%plan, err)
      if (allocated(err)) return
      call solid_init(p, g%name, lp%t, x0, g%mat_params, 0.0_wp, &
        spread(0.0_wp, 1, size(x0, 1)), pres, vpres, err)
      if (allocated(err)) return
      call solid_set_owned(p, lp%own_point, lp%own_node)
      p%part%nglob = lp%nglob
      p%part%qglob = lp%qglob
      p%part%np_whole = solid_np_whole(g)
      p%part%nq_whole = solid_nq_whole(g)
      ! the whole solid's options: RKPM's SCNI stabilization (elements have none), the
      ! health limits
      p%opt = g%opt
      call solid_set_gravity(p, p%opt%gravity)
      if (allocated(bc_of)) call move_alloc(bc_of, p%bc_of)
      p%state%v = v
      p%acc%ke0 = 0.0_wp
      do j = 1, size(p%part%own_n)
        i = p%part%own_n(j)
        p%acc%ke0 = p%acc%ke0 + 0.5_wp*p%t%mass(i)*sum(p%state%v(:, i)**2)
      end do
      p%acc%ke = p%acc%ke0
      p%spacing = g%spacing
      p%dt_cal = g%dt_cal
      allocate(h%w(2*p%t%dims%ndim, p%np))
    end associate
  end subroutine make_part

  !> Part p of solid k from the whole solid read from a checkpoint (every local node and
  !! point, ghosts too: the exchanges need not run before the first step); the energies,
  !! sums over the ranks, on rank 0.
  subroutine restart_part(dom, k, p, err)
    type(mpi_domain_t), intent(in) :: dom
    integer, intent(in) :: k
    type(solid_t), intent(inout) :: p
    type(error_t), allocatable, intent(inout) :: err
    associate (g => dom%gs(k))
      ! the rows of the part's own and ghost nodes and points, from the file
      call checkpoint_read_part(dom%restart_from, p, err)
      if (allocated(err)) return
      p%state%ipoint_time = g%state%ipoint_time
      p%kappa = g%kappa
      p%dt_cal = g%dt_cal
      call solid_set_energies(p, merge(solid_energies(g), 0.0_wp, dom%root))
    end associate
  end subroutine restart_part

  !> Every part's owned values into rank 0's whole solids (for output and measures); with
  !! state = .false. rank 0's whole solids as they are (sizes and tables), no gather.
  function mpi_whole(dom, solids, full, state) result(w)
    class(mpi_domain_t), intent(inout), target :: dom
    type(solid_t), intent(inout), target :: solids(:)
    logical, intent(in) :: full
    logical, intent(in), optional :: state
    type(solid_t), pointer :: w(:)
    integer :: k
    w => dom%gs
    if (present(state)) then
      if (.not. state) return
    end if
    ! (rank 0 kept no whole solids: nothing asks for their state then)
    if (.not. dom%root_whole) return
    dom%gathers = dom%gathers + 1
    do k = 1, size(solids)
      call gather_solid(dom, solids(k), dom%lp(k), dom%gs(k), full)
    end do
  end function mpi_whole

  !> The owned values of part p into rank 0's whole solid g: what output and the measures
  !! need, and with full what a checkpoint holds besides (a, the reactions, P, the back
  !! stress, the plastic strain rate).
  subroutine gather_solid(dom, p, lp, g, full)
    type(mpi_domain_t), intent(in) :: dom
    type(solid_t), intent(in) :: p
    type(local_part_t), intent(in) :: lp
    type(solid_t), intent(inout) :: g
    logical, intent(in) :: full
    real(wp), allocatable :: sn(:, :), sq(:, :), rn(:, :), rq(:, :)
    integer, allocatable :: idn(:), idq(:), rin(:), riq(:), cn(:), cq(:), dn(:), dq(:)
    integer, allocatable :: kn(:), kq(:)
    integer :: j, no, nqo, mn, mq, nranks
    nranks = dom%ranks%nranks
    kn = pack([(j, j = 1, size(state_fields))], state_fields%nodal .and. &
      (full .or. state_fields%snapshot))
    kq = pack([(j, j = 1, size(state_fields))], .not. state_fields%nodal .and. &
      (full .or. state_fields%snapshot))
    mn = sum([(solid_field_rows(p, kn(j)), j = 1, size(kn))])
    mq = sum([(solid_field_rows(p, kq(j)), j = 1, size(kq))])
    no = size(p%part%own_n)
    nqo = size(p%part%own_q)
    allocate(sn(mn, no), sq(mq, nqo), cn(nranks), cq(nranks), dn(nranks), dq(nranks))
    idn = lp%nglob(p%part%own_n)
    idq = lp%qglob(p%part%own_q)
    call pack_fields(p, kn, p%part%own_n, sn)
    call pack_fields(p, kq, p%part%own_q, sq)
    call MPI_Gather(no, 1, MPI_INTEGER, cn, 1, MPI_INTEGER, 0, dom%mcomm)
    call MPI_Gather(nqo, 1, MPI_INTEGER, cq, 1, MPI_INTEGER, 0, dom%mcomm)
    if (dom%root) then
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
    call MPI_Gatherv(idn, no, MPI_INTEGER, rin, cn, dn, MPI_INTEGER, 0, dom%mcomm)
    call MPI_Gatherv(idq, nqo, MPI_INTEGER, riq, cq, dq, MPI_INTEGER, 0, dom%mcomm)
    call MPI_Gatherv(sn, mn*no, MPI_DOUBLE_PRECISION, rn, mn*cn, mn*dn, &
      MPI_DOUBLE_PRECISION, 0, dom%mcomm)
    call MPI_Gatherv(sq, mq*nqo, MPI_DOUBLE_PRECISION, rq, mq*cq, mq*dq, &
      MPI_DOUBLE_PRECISION, 0, dom%mcomm)
    if (.not. dom%root) return
    call unpack_fields(g, kn, rin, rn)
    call unpack_fields(g, kq, riq, rq)
    g%state%ipoint_time = p%state%ipoint_time
    ! (calibrated on the parts, after the split: the same on every rank)
    g%dt_cal = p%dt_cal
  end subroutine gather_solid

  !> buf(:, j): the state fields ks of solid s at entry idx(j), one after another.
  subroutine pack_fields(s, ks, idx, buf)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: ks(:), idx(:)
    real(wp), intent(out) :: buf(:, :)
    integer :: j, r0, rows
    r0 = 0
    do j = 1, size(ks)
      rows = solid_field_rows(s, ks(j))
      call solid_get_field(s, ks(j), buf(r0 + 1:r0 + rows, :), idx)
      r0 = r0 + rows
    end do
  end subroutine pack_fields

  !> The state fields ks of solid s at entry idx(j) from buf(:, j) (pack_fields' layout).
  subroutine unpack_fields(s, ks, idx, buf)
    type(solid_t), intent(inout) :: s
    integer, intent(in) :: ks(:), idx(:)
    real(wp), intent(in) :: buf(:, :)
    integer :: j, r0, rows
    r0 = 0
    do j = 1, size(ks)
      rows = solid_field_rows(s, ks(j))
      call solid_put_field(s, ks(j), buf(r0 + 1:r0 + rows, :), idx)
      r0 = r0 + rows
    end do
  end subroutine unpack_fields

  function mpi_pairs(dom, pairs) result(w)
    class(mpi_domain_t), intent(inout), target :: dom
    type(contact_pair_t), intent(inout), target :: pairs(:)
    type(contact_pair_t), pointer :: w(:)
    if (allocated(dom%pairs_whole)) then
      w => dom%pairs_whole
    else
      w => pairs
    end if
  end function mpi_pairs

  integer function mpi_nodes(dom, solids, k) result(n)
    class(mpi_domain_t), intent(in) :: dom
    type(solid_t), intent(in) :: solids(:)
    integer, intent(in) :: k
    n = dom%gs(k)%np
    if (size(solids) < 0) continue
  end function mpi_nodes

  integer function mpi_points(dom, solids, k) result(n)
    class(mpi_domain_t), intent(in) :: dom
    type(solid_t), intent(in) :: solids(:)
    integer, intent(in) :: k
    n = dom%gs(k)%nq
    if (size(solids) < 0) continue
  end function mpi_points

  !> Maxima over the ranks: body_measures' values to the bit, without a gather.
  function mpi_measures(dom, s) result(m)
    class(mpi_domain_t), intent(inout) :: dom
    type(solid_t), intent(inout) :: s
    type(measures_t) :: m
    m = body_measures_part(s, dom%ranks)
  end function mpi_measures

  !> The step's contact statistics over the ranks (counts and force summed, the rest the
  !! largest; the tracked edge in contact on its owner), and the most particles each pair
  !! flagged in one step over all ranks.
  subroutine mpi_stats(dom, c, pairs)
    class(mpi_domain_t), intent(inout) :: dom
    type(contact_stats_t), intent(inout) :: c
    type(contact_pair_t), intent(inout) :: pairs(:)
    integer :: ni(4), nt(4), k, j
    real(wp) :: rm(3), rmt(3)
    integer :: nf(3, size(pairs)), nft(3, size(pairs))
    type(exact_sum_t) :: xs(stat_sums*size(pairs))
    real(wp) :: pft(stat_sums*size(pairs))
    ni = [c%n_contact, c%n_flagged, c%n_cmp_det, merge(1, 0, c%edge_in_contact)]
    call MPI_Allreduce(ni, nt, 4, MPI_INTEGER, MPI_SUM, dom%mcomm)
    rm = [c%radius, c%pen_before, c%pen_after]
    call MPI_Allreduce(rm, rmt, 3, MPI_DOUBLE_PRECISION, MPI_MAX, dom%mcomm)
    c%n_contact = nt(1)
    c%n_flagged = nt(2)
    c%n_cmp_det = nt(3)
    c%edge_in_contact = nt(4) > 0
    c%radius = rmt(1)
    c%pen_before = rmt(2)
    c%pen_after = rmt(3)
    if (size(pairs) == 0) return
    ! each pair's forces and friction work of the step (its history columns): exact sums
    ! over the ranks (the serial values to the bit); the total normal force from them, in
    ! the pairs' order (as contact_step adds them)
    xs = [(pairs(k)%step%sums, k = 1, size(pairs))]
    pft = exact_allsum_many(xs, dom%comm)
    c%force_normal = 0.0_wp
    do k = 1, size(pairs)
      associate (st => pairs(k)%step)
        do j = 1, stat_sums
          st%sums(j) = exact_sum_t()
          call exact_add(st%sums(j), pft(stat_sums*(k - 1) + j))
        end do
        call stats_values(st)
        c%force_normal = c%force_normal + st%force_normal
      end associate
    end do
    ! (each pair's flags of the step, and each detector's in compare mode, over the ranks)
    do k = 1, size(pairs)
      nf(:, k) = [pairs(k)%step%n_flagged, pairs(k)%step%n_cmp_det, pairs(k)%step%n_cmp_gap]
    end do
    call MPI_Allreduce(nf, nft, size(nf), MPI_INTEGER, MPI_SUM, dom%mcomm)
    dom%flag_max = max(dom%flag_max, int(nft(1, :), i64))
    dom%cmp_max = max(dom%cmp_max, int(nft(2:3, :), i64))
  end subroutine mpi_stats

  !> The pairs' counters summed over the ranks (most in one step: the largest); with
  !! restore each rank's own are put back after (a checkpoint's copy during the run).
  subroutine mpi_counters(dom, pairs, restore)
    class(mpi_domain_t), intent(inout) :: dom
    type(contact_pair_t), intent(inout) :: pairs(:)
    logical, intent(in) :: restore
    type(contact_counters_t), allocatable :: keep(:)
    integer :: k
    integer(i64) :: a(10), b(10)
    real(wp) :: g
    if (restore) allocate(keep(size(pairs)), source=[(pairs(k)%count, k = 1, size(pairs))])
    do k = 1, size(pairs)
      associate (c => pairs(k)%count)
        ! (exact: the serial value to the bit; the sum itself for a checkpoint)
        c%w_friction_sum = exact_allmerge(c%w_friction_sum, dom%comm)
        c%w_friction = exact_value(c%w_friction_sum)
        a = [c%screened, c%evaluated, c%detected, c%contacts, c%skipped, c%self_unsure, &
          c%cmp_det, c%cmp_gap, c%cmp_buffer, c%cmp_missed]
        call MPI_Allreduce(a, b, size(a), MPI_INTEGER8, MPI_SUM, dom%mcomm)
        c%screened = b(1)
        c%evaluated = b(2)
        c%detected = b(3)
        c%contacts = b(4)
        c%skipped = b(5)
        c%self_unsure = b(6)
        c%cmp_det = b(7)
        c%cmp_gap = b(8)
        c%cmp_buffer = b(9)
        c%cmp_missed = b(10)
        ! (compare_detectors: the buffer zone's gaps, exactly; its depth)
        c%buffer_gap_exact = exact_allmerge(c%buffer_gap_exact, dom%comm)
        c%buffer_gap_sum = exact_value(c%buffer_gap_exact)
        call MPI_Allreduce(c%buffer_gap_max, g, 1, MPI_DOUBLE_PRECISION, MPI_MAX, dom%mcomm)
        c%buffer_gap_max = g
        ! (the most flagged in one step over all ranks: mpi_stats)
        c%detected_max = dom%flag_max(k)
        c%cmp_det_max = dom%cmp_max(1, k)
        c%cmp_gap_max = dom%cmp_max(2, k)
      end associate
    end do
    if (.not. restore) return
    do k = 1, size(pairs)
      pairs(k)%count = keep(k)
    end do
  end subroutine mpi_counters

  !> The solids' datasets of snapshot lab: rank 0 closes the run's file, every rank opens
  !! it with MPI-IO and writes its part's rows collectively, and rank 0 opens it again (no
  !! rank gathers the state).
  subroutine mpi_snapshot(dom, out, lab, r, solids, err, pairs)
    class(mpi_domain_t), intent(inout) :: dom
    type(run_files_t), intent(inout) :: out
    character(len=*), intent(in) :: lab
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(inout) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    type(contact_pair_t), intent(inout), optional :: pairs(:)
    type(h5file_t) :: f
    character(len=:), allocatable :: path
    call all_open(dom, out, f, path, err)
    if (dom%any_error(err)) return
    call snapshot_write(f, lab, r%t, r%n, solids, err)
    if (present(pairs) .and. .not. allocated(err)) call self_det_out(f, lab, pairs, solids, &
      err)
    call all_close(dom, out, f, path, err)
  end subroutine mpi_snapshot

  !> A phase where every rank writes the run's file (collectively): rank 0 closes its
  !! handle and all open the file with MPI-IO as f (path: its name on every rank); err on
  !! this rank, any_error tells all.
  subroutine all_open(dom, out, f, path, err)
    class(mpi_domain_t), intent(inout) :: dom
    type(run_files_t), intent(inout) :: out
    type(h5file_t), intent(out) :: f
    character(len=:), allocatable, intent(out) :: path
    type(error_t), allocatable, intent(inout) :: err
    path = ''
    if (dom%root) path = out%f%path
    call dom%ranks%bcast_text(0, path)
    if (dom%root) call h5_close(out%f, err)
    if (dom%any_error(err)) return
    call h5_open_collective(f, path, dom%mcomm, err)
  end subroutine all_open

  !> The end of all_open's phase: all close f, rank 0 opens the file again for itself.
  subroutine all_close(dom, out, f, path, err)
    class(mpi_domain_t), intent(inout) :: dom
    type(run_files_t), intent(inout) :: out
    type(h5file_t), intent(inout) :: f
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    call h5_close_collective(f, err)
    if (dom%any_error(err)) return
    if (dom%root) call h5_open_rw(out%f, path, err)
  end subroutine all_close

  !> The bodies the ranks hold as shares (body_keep_share: mfcd_mpi's deformable bodies)
  !! into /bodies of the run's file, every rank its rows (run_output_m write_body_rows),
  !! collectively; rank 0 wrote the rest of each body (write_bodies) and keeps the file.
  subroutine mpi_bodies_rows(dom, out, bodies, err)
    class(mpi_domain_t), intent(inout) :: dom
    type(run_files_t), intent(inout) :: out
    type(body_t), intent(in) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    type(h5file_t) :: f
    character(len=:), allocatable :: path
    if (.not. any(bodies%row0 > 0)) return
    call all_open(dom, out, f, path, err)
    if (dom%any_error(err)) return
    call write_body_rows(f, bodies, err)
    call all_close(dom, out, f, path, err)
  end subroutine mpi_bodies_rows

  !> A checkpoint of the state after step r%n in the serial layout, which any number of
  !! ranks can restart from (the ghost sets of contact start afresh, which is exact): rank
  !! 0 writes the record, the solids' sizes and scalars (the energies and the pairs'
  !! counters summed over the ranks), the contacts and the history; then every rank writes
  !! its part's rows of the state fields and its own slave particles' rows of skip_far's
  !! schedule into it with MPI-IO, collectively (no gather), and rank 0 renames it over
  !! the previous checkpoint.
  subroutine mpi_checkpoint(dom, out, bodies, r, solids, pairs, t_loop, err)
    class(mpi_domain_t), intent(inout), target :: dom
    type(run_files_t), intent(inout) :: out
    type(body_t), intent(in) :: bodies(:)
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(inout), target :: solids(:)
    type(contact_pair_t), intent(inout), target :: pairs(:)
    real(wp), intent(in) :: t_loop
    type(error_t), allocatable, intent(inout) :: err
    type(h5file_t) :: f
    character(len=:), allocatable :: path
    integer :: k
    type(exact_sum_t) :: e(8)
    real(wp) :: et(8), phase(3), wall0(3, size(solids))
    do k = 1, size(solids)
      ! the accounts the history records: exact sums over the parts' entries
      e = exact_sum_t()
      call solid_account_sums(solids(k), e)
      et = exact_allsum_many(e, dom%comm)
      ! the wall times of kinematics, material and internal force: the parts' mean over
      ! the ranks added to what the whole solid holds (a restart's), for the file only
      phase = solids(k)%acc%wall
      call dom%comm%sum_real(phase)
      if (.not. dom%root) cycle
      wall0(:, k) = dom%gs(k)%acc%wall
      dom%gs(k)%acc%wall = wall0(:, k) + phase/real(dom%comm%nranks, wp)
      call solid_set_energies(dom%gs(k), et)
      dom%gs(k)%kappa = solids(k)%kappa
      dom%gs(k)%dt_cal = solids(k)%dt_cal
      dom%gs(k)%state%ipoint_time = solids(k)%state%ipoint_time
    end do
    call counters_then_write()
    if (dom%any_error(err)) return
    path = ''
    if (dom%root) path = out%path%tmp_checkpoint
    call dom%ranks%bcast_text(0, path)
    call h5_open_collective(f, path, dom%mcomm, err)
    if (dom%any_error(err)) then
      if (dom%root) call run_files_checkpoint_failed(out, r, err)
      return
    end if
    call checkpoint_write_fields(f, solids, pairs, err)
    call h5_close_collective(f, err)
    if (dom%any_error(err)) then
      if (dom%root) call run_files_checkpoint_failed(out, r, err)
      return
    end if
    if (dom%root) call run_files_checkpoint_commit(out, r, err)
  contains
    !> The summed counters in the file, each rank's own kept for the run.
    subroutine counters_then_write()
      type(contact_counters_t), allocatable :: keep(:)
      integer :: j
      allocate(keep(size(pairs)), source=[(pairs(j)%count, j = 1, size(pairs))])
      call mpi_counters(dom, pairs, .false.)
      ! (skip_far's schedule: its count and bound here, every rank's own particles' rows
      ! with the fields)
      if (dom%root) then
        call run_files_checkpoint(out, bodies, r, dom%gs, pairs, t_loop, err, fields=.false.)
        do j = 1, size(solids)
          dom%gs(j)%acc%wall = wall0(:, j)
        end do
      end if
      do j = 1, size(pairs)
        pairs(j)%count = keep(j)
      end do
    end subroutine counters_then_write
  end subroutine mpi_checkpoint

  !> The bytes the halo exchanges moved, over all ranks, per step; contact's ghost sets
  !! (log lines of rank 0).
  subroutine mpi_finish(dom, solids, pairs, r)
    class(mpi_domain_t), intent(inout) :: dom
    type(solid_t), intent(in) :: solids(:)
    type(contact_pair_t), intent(inout) :: pairs(:)
    type(run_record_t), intent(in) :: r
    integer(i64) :: loc(2), tot(2), b(1), bt(1)
    integer :: k, ng(2), ngt(2), nref(2), held(2), whole(2), nfac(2), nfw(2)
    real(wp) :: gh(2), ght(2)
    character(len=240) :: line
    loc = 0
    ng = 0
    do k = 1, size(solids)
      loc = loc + [dom%halos(k)%plan%bytes_nodes, dom%halos(k)%plan%bytes_points]
      ng = ng + [solids(k)%np - size(solids(k)%part%own_n), &
        solids(k)%nq - size(solids(k)%part%own_q)]
    end do
    call MPI_Allreduce(loc, tot, 2, MPI_INTEGER8, MPI_SUM, dom%mcomm)
    call MPI_Allreduce(ng, ngt, 2, MPI_INTEGER, MPI_SUM, dom%mcomm)
    if (dom%root) then
      write(line, '(a,i0,a,i0,a,i0,a,es10.3,a,es10.3,a)') 'summary: MPI: ', &
        dom%ranks%nranks, ' rank(s), ', ngt(1), ' ghost nodes and ', ngt(2), &
        ' ghost points; the halos moved ', real(tot(1), wp)/max(r%n, 1), ' B (nodes) and ', &
        real(tot(2), wp)/max(r%n, 1), ' B (points) per step'
      write(*, '(a)') trim(line)
    end if
    ! contact with deforming masters: the refreshes of the ghost sets, the ghost master
    ! particles (mean over the passes, summed over the ranks), the bytes contact moved
    b = dom%ranks%bytes
    call MPI_Allreduce(b, bt, 1, MPI_INTEGER8, MPI_SUM, dom%mcomm)
    do k = 1, size(pairs)
      if (.not. allocated(pairs(k)%dist)) cycle
      call contact_dist_report(pairs(k), nref, gh, held, whole, nfac, nfw)
      call MPI_Allreduce(gh, ght, 2, MPI_DOUBLE_PRECISION, MPI_SUM, dom%mcomm)
      call MPI_Allreduce(MPI_IN_PLACE, held, 2, MPI_INTEGER, MPI_MAX, dom%mcomm)
      call MPI_Allreduce(MPI_IN_PLACE, nfac, 2, MPI_INTEGER, MPI_MAX, dom%mcomm)
      if (.not. dom%root) cycle
      write(line, '(a,i0,a,i0,a,i0,a,f0.1,a,f0.1,a,es10.3,a)') 'summary: MPI: contact ', &
        k, ': ghost sets refreshed ', nref(1), ' and ', nref(2), &
        ' times (slave, master as masters), ', ght(1), ' and ', ght(2), &
        ' ghost particles on average; contact moved ', real(bt(1), wp)/max(r%n, 1), &
        ' B per step'
      write(*, '(a)') trim(line)
      ! (what a rank holds of the sides: its own and ghost particles, not the whole body)
      write(line, '(a,i0,a,i0,a,i0,a,i0,a,i0,a)') 'summary: MPI: contact ', k, &
        ': a rank''s sides held at most ', held(1), ' and ', held(2), ' particles (of ', &
        whole(1), ' and ', whole(2), ')'
      write(*, '(a)') trim(line)
      ! (3D: of the sides' surfaces, the facets of a rank's own particles, not the whole)
      if (any(nfw == 0)) cycle
      write(line, '(a,i0,a,i0,a,i0,a,i0,a,i0,a)') 'summary: MPI: contact ', k, &
        ': a rank kept at most ', nfac(1), ' and ', nfac(2), ' facets of the sides'' '// &
        'surfaces (of ', nfw(1), ' and ', nfw(2), ')'
      write(*, '(a)') trim(line)
    end do
  end subroutine mpi_finish

  subroutine halo_node_array(h, x)
    class(mpi_halo_t), intent(inout) :: h
    real(wp), intent(inout) :: x(:, :)
    call halo_nodes(h%plan, x)
  end subroutine halo_node_array

  !> Two nodal arrays x, y (ndim, local nodes) in one exchange.
  subroutine halo_node_pair(h, x, y)
    class(mpi_halo_t), intent(inout) :: h
    real(wp), intent(inout) :: x(:, :), y(:, :)
    integer :: nd
    nd = size(x, 1)
    h%w(1:nd, :) = x
    h%w(nd + 1:2*nd, :) = y
    call halo_nodes(h%plan, h%w)
    x = h%w(1:nd, :)
    y = h%w(nd + 1:2*nd, :)
  end subroutine halo_node_pair

  subroutine halo_point_array(h, x)
    class(mpi_halo_t), intent(inout) :: h
    real(wp), intent(inout) :: x(:, :)
    call halo_points(h%plan, x)
  end subroutine halo_point_array
end module mpi_domain_m
