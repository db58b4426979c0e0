!> Contact pairs of a dynamic run (deck group &contact), Sections 2 and 5.
!!
!! Each side of a pair is a body with its det(M) cloud and its surface. A rigid side never
!! moves: its cloud, bins and surface are built once. A deformable side is re-binned at its
!! predicted positions every step. Each step, between the prediction (64) and the force
!! evaluation (62), a pass from side A (slave) to side B (master) screens A's particles by
!! B's grown bounding box, evaluates det(M_B) at their predicted physical positions, measures
!! the gap of the detected ones to B's closest segment, computes the eq. (93)-(96) force at
!! each penetrating particle (with the reduced mass when B moves), applies the reaction to
!! the ends of B's segment, has the solid spread the point forces onto its nodal
!! coefficients (eq. 98 for particles, eq. 99 for element nodes), and corrects a_n and the
!! prediction. With a rigid master one pass is made (the first condition of eq. 28); when
!! both bodies deform, a second pass swaps the roles (both conditions of eq. 28).
!!
!! The detector is the pair's choice (&contact detector): det(M_B) > threshold, the paper's
!! (eqs. 25-28), or the conventional node-to-segment search of contact_nts_m (bucket sort of
!! B's segments, closest-segment projection, flagged when g < 0), the paper's comparison.
!! Either way the gap decides and the forces, friction and redistribution are the same
!! code. With compare_detectors both are also evaluated side by side for the counters only.
!!
!! Contact sees a deformable body only through the solid interface (solid_m): the points it
!! detects are the nodes' physical points, whatever the discretization behind them. Its
!! inputs are plain parameters (contact_params_t) and bodies; the caller names the deck.
!!
!! Three dimensions (bodies with ndim = 3, serial): the same passes with det(M) of the
!! master (eqs. 25-28), the gap and outward normal from the master's closed triangle
!! surface (body_t%facets, surface3d_m: the closest facet and the barycentric coordinates
!! of the closest point), the eq. (93) force along that normal, friction in the tangent
!! plane (eqs. 94-96 with the slip vector), and the reactions on a deformable master
!! spread to the closest facet's three vertices by those barycentric weights (where the
!! plane spreads to a segment's two ends by xi). Not in 3D (refused at set-up): the
!! node-to-segment detector and the comparison, self-contact, axisymmetry, ranks.
module contact_pair_m
  use kinds_m, only: wp, i64
  use dims_m, only: max_dim
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use body_m, only: body_t
  use rk_cloud_m, only: rk_cloud_t, cloud_det, cloud_init, cloud_move, cloud_set_reference, &
    cloud_det_excluding, cloud_clearance
  use detection_m, only: body_plateau, detection_threshold, body_cloud
  use contact_m, only: master_surface_t, surface_build, surface_update, surface_gap, &
    contact_point_force, contact_counters_t, surface_subset, contact_point_force_3d
  use surface3d_m, only: surface3d_t, surface3d_build, surface3d_update, surface3d_gap, &
    surface3d_of
  use contact_nts_m, only: nts_buckets_t, nts_build, nts_update, nts_gap
  use omp_lib, only: omp_get_wtime
  use solid_m, only: solid_t, solid_positions, solid_point_position, solid_add_point_forces, &
    solid_correct, at_step_start, at_prediction, solid_share_corrections, solid_node_place
  use rank_comm_m, only: rank_comm_t
  use solid_tables_m, only: solid_tables_t
  use exact_sum_m, only: exact_sum_t, exact_add, exact_merge, exact_value
  use sorting_m, only: sort_index, sorted_place
  use generators_m, only: lattice_node
  implicit none
  private
  public :: contact_pair_t, contact_params_t, contact_pair_init, contact_correct, side_facts_t
  public :: side_loop_surface
  public :: contact_stats_t, contact_det_fields, contact_step
  public :: detector_det_m, detector_nts, detector_name, contact_self_det, side_np_whole
  public :: contact_pair_localize, contact_pair_cut, contact_pair_distribute, contact_pair_own, &
    contact_dist_report
  ! (public for the submodule contact_dist_sm only: gfortran 12 leaves out a private module
  ! procedure the submodule calls, even one the module calls too)
  public :: detect_det_m, pass_forces, detect_self, spreads, detect_det_m_3d, pass_forces_3d
  public :: detect_self_3d, self_schedule, self_settled, lip_over_ranks
  public :: stat_sums, stats_values, side_whole, side_take, take_i1

  !> Detectors (&contact detector): det(M) of the master (the paper), node-to-segment.
  integer, parameter :: detector_det_m = 1, detector_nts = 2

  !> contact_stats_t's exact sums: |f_n|, |f_t|, the slave's force (3), the friction work
  integer, parameter :: stat_sums = 6

  !> Self-contact skipping: a step that re-bins the body screens also the surface
  !! particles due within this many more steps (bench/self_contact.py)
  integer, parameter :: self_lookahead = 32
  !> self-contact skipping: a candidate's clearance is searched up to this fraction of its
  !! neighbour radius rex (bench/self_contact.py, doc/benchmarks.md)
  real(wp), parameter :: self_reach = 0.125_wp
  !> In axisymmetry a surface point within this fraction of the body's spacing of the axis
  !! r = 0 lies on it, and a segment with both ends there is no surface: far above the
  !! round-off of a coordinate, far below any particle's distance from the axis.
  real(wp), parameter :: axis_fraction = 1.0e-9_wp
  !> skip_far's schedule shortens each distance by this relative amount, for the rounding of
  !! the sums that gave it (a few ulps; 1e-9 leaves a margin of 10^6 of them), so a point is
  !! never skipped past the step it could first arrive.
  real(wp), parameter :: skip_rounding = 1.0e-9_wp

  !> A pair's parameters (deck group &contact).
  type :: contact_params_t
    real(wp) :: eps_cr = 5.0e-10_wp      !< det(M_master) threshold (paper: 5e-10)
    real(wp) :: eps_rel = 0.0_wp         !< or this fraction of the master's plateau (> 0)
    real(wp) :: mu = 0.0_wp              !< Coulomb friction coefficient
    integer :: detector = detector_det_m !< detector_det_m or detector_nts
    logical :: compare = .false.         !< also run the other detector, for the counters
    logical :: skip_far = .true.         !< skip slave particles that cannot reach the master
    logical :: track_edge = .false.      !< report contact/separation of one slave node
    real(wp) :: edge_point(max_dim) = 0.0_wp   !< its reference position (m): the nearest node
    !> Effective mass of eq. (93) against a deformable master. .true. (the default): each
    !! master node's mass shared among the particles that push it (the row sum of the
    !! constraint's mass matrix), so they do not each claim its whole mobility and
    !! over-correct together (doc/contact.md). .false.: the reduced mass of the particle
    !! and its master point alone, as if no other particle pushed the same segment ends
    !! (their forces then alternate from step to step where the spacings do not match).
    logical :: shared_mass = .true.
    !> Self-contact, where slave and master are the same body (Sections 1 and 7). A point's
    !! neighbours in the reference configuration, the particles within self_radius times
    !! its largest support of it there, or times their own, the larger (symmetric), take no
    !! part in its det(M) and their segments none in its gap.
    logical :: self_contact = .false.
    real(wp) :: self_radius = 2.0_wp
    !> a rigid master's prescribed velocity (m/s; its &body velocity): it moves by
    !! master_velocity x t from its reference position (a ram, a die)
    real(wp) :: master_velocity(max_dim) = 0.0_wp
  end type contact_params_t

  !> What one step's contact did (for the log, history and summary).
  type :: contact_stats_t
    integer :: n_contact = 0            !< particles with a force this step
    integer :: n_flagged = 0            !< particles the pair's detector flagged this step
    integer :: n_cmp_det = 0, n_cmp_gap = 0   !< flagged by each detector (compare mode)
    !> Mean normal contact force over the step (N, N/m in plane strain): half the sum of the
    !! eq. (93) forces, since a force added to a_n gives the velocity the impulse dt/2 f
    !! (eq. 63) and is absent at n+1.
    real(wp) :: force_normal = 0.0_wp
    !> the same for the friction forces of eqs. (94)-(96): half the sum of their
    !! magnitudes (N, N/m)
    real(wp) :: force_tangential = 0.0_wp
    !> the resultant contact force on the slave body over the step (N, N/m), half the sum
    !! of the slave particles' forces and of the opposites of the master particles' (the
    !! second condition of eq. 28), in x, y (plane) or r, z, and in x, y, z in 3D (the third
    !! 0 in the plane): the force the pair transmits
    real(wp) :: force_slave(3) = 0.0_wp
    !> the work of the friction forces of eqs. (94)-(96) over the step on the relative
    !! tangential motion (J, J/m; <= 0): per particle 1/2 f_t s_c, the mean force of the
    !! step (as force_tangential) times the slip s_c left after the correction, s_c = s +
    !! dt^2/2 f_t/m (s the predicted slip of eq. 90, m the eq. 93 mass): 0 where a particle
    !! sticks, -1/2 mu |f_n| |s_c| where it slides
    real(wp) :: w_friction = 0.0_wp
    !> the sums behind them, exact (exact_sum_m): of the normal forces, of the tangential
    !! forces' magnitudes, of the slave's force in x, y (r, z), z, and of the friction work (twice
    !! the forces above, the work itself); on ranks over this rank's particles until
    !! summed over the ranks (the same bits on any number of ranks and threads)
    type(exact_sum_t) :: sums(stat_sums)
    real(wp) :: radius = 0.0_wp         !< largest x1 of a contacting particle (m)
    real(wp) :: pen_before = 0.0_wp     !< deepest predicted penetration (m, >= 0)
    real(wp) :: pen_after = 0.0_wp      !< deepest penetration left after the correction (m)
    logical :: edge_in_contact = .false.
  end type contact_stats_t

  !> What a side over a rank's region of a 3D body that no rank holds whole (a deforming
  !! master's or a self-contact's, made per rank) takes of the whole body, found over the
  !! ranks by the set-up (dynamic_setup_m side_facts): det(M)'s interior plateau and its
  !! median at the surface particles (detection_m share_det_medians), the largest support,
  !! the reference positions' extremes, and the part of the closed surface near the
  !! rank's region (every facet with a vertex there, surface3d_m surface3d_part: the
  !! facets, their numbers and partners in the whole surface, their vertices' positions,
  !! the whole surface's cell size and counts). Each is the serial side_init's value, to
  !! the bit (the surface's restricted to those facets).
  type :: side_facts_t
    real(wp) :: plateau = 0.0_wp, surface_det = 0.0_wp
    integer :: nf_most = 0               !< the most facets of the surface a rank took (log)
    real(wp) :: rmax(3) = 0.0_wp, lo(3) = 0.0_wp, hi(3) = 0.0_wp
    type(surface3d_t) :: surf3
    !> a plane body's (a rectangle made per rank): its whole boundary polyline, its ends the
    !! whole body's numbers (side_loop_surface), as side_init builds it from the whole body
    type(master_surface_t) :: surf2
  end type side_facts_t

  !> One body of a pair as contact sees it.
  type :: side_t
    character(len=64) :: name = ''
    integer :: isolid = 0                !< index of its solid; 0 if rigid
    integer :: np = 0
    !> its arrays cut to a rank's part (contact_pair_cut)
    logical :: cut = .false.
    integer :: ndim = 2                  !< 2 (plane, axisymmetry) or 3
    type(rk_cloud_t) :: cloud            !< det(M) of this body (current positions)
    type(master_surface_t) :: surface    !< its boundary polylines (2D)
    !> its closed triangle surface (3D; body_t%facets): seg holds the facet a penetrating
    !! particle hit, bary (3, np) the barycentric coordinates of its closest point there
    type(surface3d_t) :: surf3
    real(wp), allocatable :: bary(:, :)
    type(nts_buckets_t) :: buckets       !< its segments bucket-sorted (node-to-segment)
    real(wp) :: plateau = 0.0_wp, threshold = 0.0_wp
    real(wp) :: surface_det = 0.0_wp     !< median det(M) at the body's own boundary particles
    real(wp), allocatable :: lo(:), hi(:)   !< box grown by the largest support (ndim)
    real(wp), allocatable :: x_old(:, :), x_pred(:, :)  !< physical positions (ndim, np)
    real(wp), allocatable :: rho(:, :)   !< supports (ndim, np): reach of the segment search
    real(wp), allocatable :: x_ref(:, :), vol(:)   !< reference positions (m), volumes (m^2)
    integer :: kid = 0, wshape = 0, bid = 0
    real(wp), allocatable :: h(:)        !< the cloud's basis scale (ndim)
    !> a rigid side that moves (a ram): its velocity (m/s) and its displacement at the
    !! prediction (m); its cloud, bins, surface and box stay at the reference positions and
    !! a point x is looked up at x - shift. Zero for every other side.
    logical :: moving = .false.
    real(wp), allocatable :: vel(:), shift(:)
    real(wp), allocatable :: fphys(:, :) !< contact forces at the particles this pass (N)
    logical, allocatable :: active(:)    !< particle carries a force this pass
    integer, allocatable :: seg(:)       !< the segment each penetrating particle hit
    real(wp), allocatable :: xi(:)       !< where on it
    real(wp), allocatable :: gap(:)      !< its gap (m, < 0)
    real(wp), allocatable :: nrm(:, :), tng(:, :)  !< the segment's normal, tangent (ndim, np)
    !> inverse particle masses (1/kg); 0 for a rigid side and for a node whose velocity is
    !! prescribed in both components
    real(wp), allocatable :: imass(:)
    ! skipping far particles (a slave against a rigid master, &contact skip_far): a particle
    ! found at distance r outside the master's grown box cannot enter it before the bound
    ! on its motion, summed over the steps since, reaches r (side_near_positions)
    logical :: skip_far = .false.
    real(wp) :: travel = 0.0_wp          !< bound on any particle's motion since t = 0 (m)
    !> on ranks: this step's max_I |d_I - d'_I|^2 over the whole body (m^2), when
    !! travels_at_once took it with the other pairs' in one reduction; < 0: not taken
    real(wp) :: dmax2_all = -1.0_wp
    real(wp) :: lip = 0.0_wp             !< |x_j - x'_j| <= lip max_I |d_I - d'_I|
    real(wp), allocatable :: due(:)      !< travel at which a particle is screened again (m)
    real(wp), allocatable :: d_scr(:, :) !< coefficients at the last screening (ndim, np) (m)
    !> a rank's part (contact_pair_localize): the ranks, over which the bound on the motion
    !! is taken, so that every particle is screened at the steps the serial run screens it
    class(rank_comm_t), pointer :: ranks => null()
    !> positions computed this step (all, unless skip_far): a particle not near is not
    !! screened; its x_pred, x_old are stale
    logical, allocatable :: near(:)
    real(wp), allocatable :: slip(:)     !< tangential slip of each penetrating particle (m)
    !> as a master: sum of the weights (1 - xi, xi) with which this pass's penetrating
    !! particles load each node, for the shared effective mass
    real(wp), allocatable :: share(:)
    ! self-contact: the candidates are the particles on the surface polylines (an interior
    ! particle is shielded by them); rex: each one's reference-neighbour radius (m)
    integer, allocatable :: cand(:)
    integer :: ncand = 0                 !< the candidates of the whole body (for the log)
    real(wp), allocatable :: rex(:)
    !> self-contact with skip_far, the first pass's: each screened candidate's clearance
    !! (cloud_clearance, m; 0 when a non-neighbour may cover it) and every particle's
    !! predicted position (ndim, np), which bound the second pass's work (self_settled)
    real(wp), allocatable :: clear(:), x_pass(:, :)
    !> self-contact (3D): flagged by the pass's det(M) (np); the surface not yet moved to
    !! the pass's positions (self_positions): moved only when a candidate is flagged
    logical, allocatable :: flagged(:)
    logical :: surf_stale = .false.
    ! the particles a pass looks at (side_select): with subcycling (subcycle_m) the
    ! solid's nodes of the rate being stepped, listed; else all (listed false, nlist = np)
    logical :: listed = .false.
    integer :: nlist = 0
    integer, allocatable :: list(:)
    !> The numbers in the whole body of the particles the arrays hold, and the whole body's
    !! count: a slave against a rigid master on a rank of a decomposed set-up (side_init's
    !! rows: the rank's region, ascending), a side of a distributed pair (dist_side_t: own
    !! then ghosts); unallocated: every particle, in order
    integer, allocatable :: glob(:)
    integer :: np_whole = 0
  end type side_t

  !> Distributed memory, one side of a pair whose master deforms, on one rank
  !! (contact_pair_distribute; doc/parallel.md, "Contact without a second decomposition"):
  !! the side's arrays hold the rank's particles only, its own first (1..nown, ascending by
  !! their numbers in the whole body, side_t glob) and then its ghosts (ascending): the
  !! particles of other ranks within the ghost width of its slave particles (and the
  !! partners of its own surface particles), refreshed when the motion since the last
  !! refresh has used up the margin. The rank computes the positions of its own; as a
  !! master it holds a cloud and a surface of its own particles and the ghosts, whose
  !! positions, reference data and inverse masses come from their owners.
  type :: dist_side_t
    integer :: nown = 0                  !< the particles this rank owns: 1..nown
    integer, allocatable :: owner(:)     !< rank of each of the rank's particles, from 0
    integer, allocatable :: gl(:)        !< each one's node in the rank's part solid, or 0
    !> the ranks owning an end (vertex) of a segment (facet) whose first this rank owns:
    !! it sends them that end's position along at every refresh (the static partners)
    integer, allocatable :: pq(:)
    !> plane: the whole surface's segments' ends, by the particles' numbers in the whole
    !! body; its geometry freed (surface-sized, not body-sized: the subset the rank holds
    !! is taken from it at a refresh)
    type(master_surface_t) :: full
    !> 3D: the whole surface's facets with a vertex among the rank's own particles (the
    !! part's surface, fixed from the split on; no rank holds the whole surface): their
    !! numbers in the whole surface (fid, ascending), vertices (ftri (3, :): the particles'
    !! numbers in the whole body), edge partners (fpart (3, :): numbers in the whole
    !! surface) and the ranks owning the vertices (fown (3, :)); each own particle's
    !! facets among them (vfac(vfptr(k) : vfptr(k+1) - 1)); the whole surface's bins' cell
    !! (m). A refresh takes the facets whose three vertices the rank holds from these and
    !! from the ghosts' owners (make_plan)
    integer, allocatable :: fid(:), ftri(:, :), fpart(:, :), fown(:, :), vfptr(:), vfac(:)
    real(wp) :: cell3 = 0.0_wp
    integer :: nf_whole = 0              !< 3D: the whole surface's facets (the log's)
    !> 3D: the largest facet edge over the whole master (m), the motion since the refresh
    !! D_s + D_m (m), and the largest radius the gap search has needed, |g| + 2 dmax (m):
    !! the ghost width covers it, or the rank refreshes and searches again (dist_covered)
    real(wp) :: dmax = 0.0_wp, moved = 0.0_wp, gcov = 0.0_wp
    !> the whole master's extremes at this pass (the cloud's bins' grid) (m)
    real(wp), allocatable :: glo(:), ghi(:)
    real(wp), allocatable :: rmax(:)     !< the whole side's largest support (ndim) (m)
    !> static partners: for each own particle (own order, CSR pptr), the ranks owning the
    !! first end of a surface segment whose second end it is (they need its position)
    integer, allocatable :: pptr(:), prank(:)
    !> the ghost plan as a master: own particles sids(sptr(k) : sptr(k+1)-1) go to rank
    !! to(k); ghosts rids(rptr(k) : rptr(k+1)-1) come from rank from(k) (the rank's
    !! numbering); loc: the rank's particles ascending by their numbers in the whole body
    !! (the order of its cloud, the serial one)
    integer, allocatable :: to(:), sptr(:), sids(:), from(:), rptr(:), rids(:), loc(:)
    !> own positions of this side (xr_m) and of the other (xr_s) at the last refresh (m)
    real(wp), allocatable :: xr_m(:, :), xr_s(:, :)
    real(wp) :: width = -1.0_wp          !< ghost width of the last refresh (m); < 0: none
    integer :: nrefresh = 0              !< refreshes so far
    integer :: held = 0                  !< the most particles the side's arrays held
    integer(i64) :: nghost_sum = 0       !< ghosts summed over the passes (for the mean)
    integer(i64) :: npass = 0
    real(wp), allocatable :: xl(:, :)    !< positions of loc (work, m)
    real(wp), allocatable :: f(:, :)     !< point forces on the part solid's nodes (work, N)
    real(wp), allocatable :: sbuf(:), rbuf(:)   !< message buffers (work)
    !> the shared mass's records sorted into the serial order (route_shares; work, grown
    !! as needed, so that no pass allocates): (master, slave, weight) triples, their keys
    real(wp), allocatable :: wrec(:), wkey(:)
    integer, allocatable :: widx(:)
    integer, allocatable :: mptr(:), nptr(:)    !< message pointers (work)
  end type dist_side_t

  !> Distributed memory, a pair whose master deforms on one rank: the ranks, the sides'
  !! plans, and the margin of the ghost width (a fraction of the width contact needs).
  type :: pair_dist_t
    class(rank_comm_t), pointer :: comm => null()
    type(dist_side_t) :: side(2)
    real(wp) :: margin = 0.5_wp
    !> testing only (mfcd_mpi --ghost-refresh=never): keep the first ghost sets, so that
    !! a contact the margin does not cover is missed (the test that proves it matters)
    logical :: refresh = .true.
    !> self-contact with skip_far: the clearance search's largest reach, self_reach x the
    !! largest neighbour radius of a candidate (m); side 2's ghost width covers it as well
    real(wp) :: clear_reach = 0.0_wp
  end type pair_dist_t

  type :: contact_pair_t
    type(side_t) :: side(2)              !< side 1 the slave, side 2 the master
    real(wp) :: eps_cr = 0.0_wp, eps_rel = 0.0_wp, mu = 0.0_wp
    integer :: detector = detector_det_m
    logical :: compare = .false.
    integer :: edge = 0                  !< slave particle tracked for separation (0: none)
    logical :: both_ways = .false.       !< both bodies deform: eq. (28) both conditions
    logical :: shared_mass = .false.     !< contact_params_t%shared_mass
    !> self-contact (contact_params_t%self_contact): both sides are views of the same body,
    !! side 2 the master in the first pass, side 1 in the second
    logical :: self = .false.
    !> self-contact: a particle's neighbour radius rex is self_radius x its largest support
    real(wp) :: self_radius = 0.0_wp
    type(contact_counters_t) :: count
    type(contact_stats_t) :: step
    !> distributed memory with a deforming master (contact_pair_distribute)
    type(pair_dist_t), allocatable :: dist
  end type contact_pair_t

  interface
    !> Distributed memory (issue 12, doc/parallel.md), the first step of making pair p, set
    !! up on the whole bodies or the ranks' regions, a rank's part of a pair whose master
    !! deforms (or of a self-contact): its side sd cut to the rank's own particles, before
    !! the part's rows are made (the split's peak). owner: the rank (from 0) of each of the
    !! side's particles (its arrays' places); vowner: of each vertex of its whole surface
    !! (3D: its facets' vertices, surface3d_t vid's order; plane: each segment's first
    !! ends, then its second ends); me, nranks: this rank, the ranks' count. No
    !! communication.
    module subroutine contact_pair_own(p, sd, owner, vowner, me, nranks, err)
      type(contact_pair_t), intent(inout) :: p
      integer, intent(in) :: sd, owner(:), vowner(:), me, nranks
      type(error_t), allocatable, intent(inout) :: err
    end subroutine contact_pair_own

    !> The second step (after contact_pair_own on both sides' solids, once the part solids
    !! exist): nglob(s): the global numbers of the nodes of the rank's part solid of side
    !! s, ascending; comm: the ranks (kept by pointer). margin: the ghost width's margin,
    !! a fraction of the width contact needs (> 0: refreshes become rarer, the ghost sets
    !! larger); refresh .false.: testing only (never refresh). Collective.
    module subroutine contact_pair_distribute(p, solids, comm, nglob1, nglob2, margin, &
      refresh, err)
      type(contact_pair_t), intent(inout) :: p
      type(solid_t), intent(in) :: solids(:)
      class(rank_comm_t), pointer, intent(in) :: comm
      integer, intent(in) :: nglob1(:), nglob2(:)
      real(wp), intent(in) :: margin
      logical, intent(in) :: refresh
      type(error_t), allocatable, intent(inout) :: err
    end subroutine contact_pair_distribute

    !> The contact corrections of distributed pair p for the step dt (contact_correct).
    module subroutine dist_correct(p, solids, dt, err)
      type(contact_pair_t), intent(inout) :: p
      type(solid_t), intent(inout) :: solids(:)
      real(wp), intent(in) :: dt
      type(error_t), allocatable, intent(inout) :: err
    end subroutine dist_correct

    !> det(M) of distributed self-contact pair p's body at the rank's own particles own
    !! (contact_self_det), from its contact cloud brought to the current positions
    !! (dist_master: the same particles, bins and order as the serial cloud). Collective.
    module subroutine dist_self_det(p, solids, det, own, err)
      type(contact_pair_t), intent(inout) :: p
      type(solid_t), intent(in) :: solids(:)
      real(wp), allocatable, intent(out) :: det(:)
      integer, allocatable, intent(out) :: own(:)
      type(error_t), allocatable, intent(inout) :: err
    end subroutine dist_self_det

    !> This rank's refreshes, mean ghost count and bytes of distributed pair p (for the
    !! log), per side as a master.
    module subroutine contact_dist_report(p, nrefresh, ghosts, held, whole, facets, nfw)
      type(contact_pair_t), intent(in) :: p
      integer, intent(out) :: nrefresh(2)
      real(wp), intent(out) :: ghosts(2)
      !> the most particles each side's arrays held on this rank (own and ghosts), and
      !! each side's body's count
      integer, intent(out) :: held(2), whole(2)
      !> 3D: the facets each side keeps on this rank (those of its own particles), and
      !! the count of its whole surface's (0: a plane side)
      integer, intent(out) :: facets(2), nfw(2)
    end subroutine contact_dist_report
  end interface

contains

  !> Pair p between the slave body bs and the master body bm; isolid_s, isolid_m index their
  !! solids in solids (0: the body is rigid). Errors name the variable; the caller adds the
  !! deck and group.
  subroutine contact_pair_init(p, prm, bs, isolid_s, bm, isolid_m, solids, axisym, err, &
    rows, rows_m, facts_s, facts_m)
    type(contact_pair_t), intent(out) :: p
    type(contact_params_t), intent(in) :: prm
    type(body_t), intent(in) :: bs, bm
    integer, intent(in) :: isolid_s, isolid_m
    type(solid_t), intent(in) :: solids(:)
    logical, intent(in) :: axisym
    type(error_t), allocatable, intent(inout) :: err
    !> a rank's region of the slave (ascending numbers in bs; side_init's rows): the slave
    !! side of a pair with a rigid master holds these particles only; so does each side
    !! of a pair whose master deforms (or of a self-contact) with rows_m the master's
    !! region, until the split cuts them to the rank's own (contact_pair_own)
    integer, intent(in), optional :: rows(:), rows_m(:)
    !> with rows and rows_m, of a side whose body (bs, bm) is a rank's region of a body no
    !! rank holds whole: what the side takes of the whole body (side_init's facts)
    type(side_facts_t), intent(in), optional :: facts_s, facts_m
    integer :: j
    real(wp) :: best
    p%eps_cr = prm%eps_cr
    p%eps_rel = prm%eps_rel
    p%mu = prm%mu
    p%detector = prm%detector
    p%compare = prm%compare
    p%shared_mass = prm%shared_mass
    p%self = prm%self_contact
    p%self_radius = prm%self_radius
    if (p%self .and. p%detector /= detector_det_m) then
      call set_error(err, "variable detector: self-contact of '"//trim(bs%name)//"' needs "// &
        "detector = 'det_m': a closest-segment search cannot tell a face that folded onto "// &
        "the body from the body's own curved surface (its distant segments lie on the far "// &
        "side of a convex point), det(M) of the non-neighbour particles can")
      return
    end if
    if (p%self .and. p%compare) then
      call set_error(err, "variable compare_detectors: not available for the self-contact "// &
        "of '"//trim(bs%name)//"' (node-to-segment has no self-contact); give .false.")
      return
    end if
    if (p%self .and. .not. (prm%self_radius >= 1.0_wp)) then
      call set_error(err, "variable self_radius: "//rtoa(prm%self_radius)//" would let "// &
        "particles whose support covers a point in the reference configuration take part "// &
        "in its det(M); give at least 1 (default 2)")
      return
    end if
    if (bs%ndim /= bm%ndim) then
      call set_error(err, "bodies '"//trim(bs%name)//"' ("//itoa(bs%ndim)//"D) and '"// &
        trim(bm%name)//"' ("//itoa(bm%ndim)//"D) cannot be in contact: give two bodies "// &
        "of the same dimension")
      return
    end if
    if (bs%ndim == 3) then
      call check_3d(prm, bs, axisym, err)
      if (allocated(err)) return
    end if
    ! (a slave against a rigid master is never a master: no det(M), no surface of its own)
    if (present(rows) .and. isolid_m == 0 .and. .not. p%self) then
      call side_init(p%side(1), bs, isolid_s, solids, axisym, p%eps_cr, p%eps_rel, err, &
        slave_only=.true., rows=rows)
    else if (present(rows) .and. present(rows_m) .and. isolid_m > 0) then
      call side_init(p%side(1), bs, isolid_s, solids, axisym, p%eps_cr, p%eps_rel, err, &
        rows=rows, facts=facts_s)
    else
      call side_init(p%side(1), bs, isolid_s, solids, axisym, p%eps_cr, p%eps_rel, err, &
        slave_only=isolid_m == 0 .and. .not. p%self)
    end if
    if (allocated(err)) return
    if (present(rows) .and. present(rows_m) .and. isolid_m > 0) then
      call side_init(p%side(2), bm, isolid_m, solids, axisym, p%eps_cr, p%eps_rel, err, &
        rows=rows_m, facts=facts_m)
    else
      call side_init(p%side(2), bm, isolid_m, solids, axisym, p%eps_cr, p%eps_rel, err)
    end if
    if (allocated(err)) return
    if (isolid_m == 0 .and. any(prm%master_velocity(1:bm%ndim) /= 0.0_wp)) then
      p%side(2)%moving = .true.
      p%side(2)%vel = prm%master_velocity(1:bm%ndim)
    end if
    if (p%self) then
      ! either side is the master in turn: det(M) of the non-neighbours needs the
      ! reference positions, the slave pass its candidates and their exclusion radii
      ! (a side over a rank's region has no cloud: the split's plans make the rank's)
      do j = 1, 2
        if (.not. allocated(p%side(j)%glob)) &
          call cloud_set_reference(p%side(j)%cloud, p%side(j)%x_ref, p%self_radius)
        call self_candidates(p%side(j), prm%self_radius)
      end do
    end if
    if (bs%ndim == 3) then
      ! (side_init has refused a 3D body without facets)
      ! (the whole surface's: a side over a rank's region may hold a part without facets)
      if (p%side(2)%surf3%nf_whole == 0 .or. &
        (isolid_m > 0 .and. p%side(1)%surf3%nf_whole == 0)) then
        call set_error(err, "body '"//trim(merge(bm%name, bs%name, &
          p%side(2)%surf3%nf_whole == 0))//"' has no surface facets")
        return
      end if
    else if (p%side(2)%surface%nseg == 0 .or. &
      (isolid_m > 0 .and. p%side(1)%surface%nseg == 0)) then
      call set_error(err, "body '"//trim(merge(bm%name, bs%name, &
        p%side(2)%surface%nseg == 0))//"' has no surface polyline")
      return
    end if
    p%both_ways = isolid_m > 0
    ! a deformable master needs all of the slave's positions (its cloud and surface move)
    if (prm%skip_far .and. .not. p%both_ways) call skip_far_init(p%side(1), solids)
    ! self-contact: skip_far skips the candidates that no non-neighbour can reach yet
    if (p%self .and. prm%skip_far) call skip_far_init(p%side(1), solids)
    ! a threshold at or above the master's interior plateau detects nothing: the bar
    ! would pass through the target silently (bench/sweeps.py, eps_cr = 1e-4)
    if ((p%detector == detector_det_m .or. p%compare) .and. &
      .not. (p%side(2)%threshold < p%side(2)%plateau)) then
      call set_error(err, "variable "//trim(merge('eps_rel', 'eps_cr ', prm%eps_rel > &
        0.0_wp))//": the threshold "//rtoa(p%side(2)%threshold)//" is not below the "// &
        "interior plateau of det(M) of '"//trim(bm%name)//"', "//rtoa(p%side(2)%plateau)// &
        ", so no penetration could be detected; give a threshold well below the plateau "// &
        "(paper: eps_cr = 5e-10)")
      return
    end if
    p%edge = 0
    if (prm%track_edge) then
      best = huge(1.0_wp)
      do j = 1, bs%np
        if (norm2(bs%x(:, j) - prm%edge_point(1:bs%ndim)) < best) then
          best = norm2(bs%x(:, j) - prm%edge_point(1:bs%ndim))
          p%edge = j
        end if
      end do
    end if
  end subroutine contact_pair_init

  !> The boundary polyline of plane body b that a rank holds a share of, made from its
  !! recipe (a rectangle: generators_m lattice_node, the whole body's positions to the bit)
  !! at the whole loop b holds (b%loop_ptr, loop_idx: the whole body's numbers,
  !! perimeter-sized): side_init's surface_build over the whole body, the same segments
  !! with the same geometry, their ends the whole body's numbers.
  subroutine side_loop_surface(b, axisym, s, err, xloop)
    type(body_t), intent(in) :: b
    logical, intent(in) :: axisym
    type(master_surface_t), intent(out) :: s
    type(error_t), allocatable, intent(inout) :: err
    !> the positions of the loops' particles b%loop_idx, when b has no recipe (a plane
    !! mesh file read per part: tri_file_m tri_file_positions)
    real(wp), intent(in), optional :: xloop(:, :)
    real(wp), allocatable :: x(:, :)
    real(wp) :: vol
    logical :: bnd
    integer :: n, k
    n = size(b%loop_idx)
    allocate(x(2, n))
    if (present(xloop)) then
      x = xloop
    else
      do k = 1, n
        call lattice_node(b%lat, b%loop_idx(k), x(:, k), vol, bnd)
      end do
    end if
    call surface_build(s, x, b%loop_ptr, [(k, k = 1, n)], b%loop_closed, axisym, &
      axis_fraction*minval(b%spacing(1:2)), err)
    if (allocated(err)) return
    s%i0 = b%loop_idx(s%i0)
    s%i1 = b%loop_idx(s%i1)
  end subroutine side_loop_surface

  !> What a 3D pair (slave body bs) cannot do: the node-to-segment detector and the
  !! detectors' comparison (a 3D closest-facet search binned like contact_nts_m's buckets
  !! is not written), axisymmetry (a 2D geometry).
  subroutine check_3d(prm, bs, axisym, err)
    type(contact_params_t), intent(in) :: prm
    type(body_t), intent(in) :: bs
    logical, intent(in) :: axisym
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: what
    what = "contact of the 3D body '"//trim(bs%name)//"': "
    if (prm%detector /= detector_det_m) then
      call set_error(err, "variable detector: "//what//"the node-to-segment detector "// &
        "is 2D only; give detector = 'det_m'")
    else if (prm%compare) then
      call set_error(err, "variable compare_detectors: "//what//"the node-to-segment "// &
        "detector it compares with is 2D only; give .false.")
    else if (axisym) then
      call set_error(err, what//"axisymmetry is a 2D geometry; give a plane or 3D run")
    end if
  end subroutine check_3d

  !> Side s of a pair over body b (solid isolid, 0: rigid). slave_only: the slave against a
  !! rigid master, which only the master's det(M), surface and buckets are read against
  !! (contact_correct): without a cloud, det(M) measures or surface of its own; with rows
  !! (ascending numbers in b), over those particles only (a rank's region of a decomposed
  !! set-up, which the split cuts to its part: contact_pair_cut); when b holds some
  !! particles of a larger body (b%glob: the region a rank made of it; a master's or a
  !! self-contact's side then takes what it needs of the whole body from facts),
  !! rows are places in b.
  subroutine side_init(s, b, isolid, solids, axisym, eps_cr, eps_rel, err, slave_only, rows, &
    facts)
    type(side_t), intent(out) :: s
    type(body_t), intent(in) :: b
    integer, intent(in) :: isolid
    type(solid_t), intent(in) :: solids(:)
    logical, intent(in) :: axisym
    real(wp), intent(in) :: eps_cr, eps_rel
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: slave_only
    integer, intent(in), optional :: rows(:)
    !> what the side takes of the whole body when b is a rank's region of it (b%glob): no
    !! cloud or surface of b's own is made
    type(side_facts_t), intent(in), optional :: facts
    logical :: own
    real(wp) :: rmax(3)
    integer :: n, i, j
    own = .true.
    if (present(slave_only)) own = .not. slave_only
    s%name = b%name
    s%np = b%np
    if (present(rows)) then
      s%glob = rows
      s%np_whole = b%np
      s%np = size(rows)
      ! (b some particles of a larger body, a rank's region: rows are places in b)
      if (allocated(b%glob)) then
        s%glob = b%glob(rows)
        s%np_whole = b%np_whole
      end if
    end if
    n = s%np
    s%isolid = isolid
    rmax = 0.0_wp
    if (b%np > 0) rmax(1:b%ndim) = maxval(b%rho, dim=2)
    if (own .and. present(facts)) then
      s%plateau = facts%plateau
      s%threshold = detection_threshold(eps_cr, eps_rel, s%plateau)
      s%surface_det = facts%surface_det
      rmax = facts%rmax
      s%cloud%rmax = rmax
    else if (own) then
      call body_cloud(b, s%cloud, err)
      if (allocated(err)) return
      s%plateau = body_plateau(b, s%cloud)
      s%threshold = detection_threshold(eps_cr, eps_rel, s%plateau)
      s%surface_det = surface_det_median(b, s%cloud)
      rmax = s%cloud%rmax
      ! a side over a rank's region (a deforming master's on ranks): the cloud over the
      ! whole body gave the detection's scalars; the split's plans make the rank's own
      if (present(rows)) then
        s%cloud = rk_cloud_t()
        s%cloud%rmax = rmax
      end if
    end if
    s%ndim = b%ndim
    if (b%ndim == 3) then
      if (.not. allocated(b%facets)) then
        call set_error(err, "body '"//trim(b%name)//"' has no closed surface of facets "// &
          "(its shape's generator could not close one): contact in 3D needs it; give a "// &
          "box, an extruded polygon or a cylinder")
        return
      end if
      ! (over a rank's region the surface is read for its facets, vertices, partners,
      ! cell and reference positions only, until the split takes the rank's subset and
      ! frees it: without normals or bins; the part near the region from facts)
      if (own .and. present(facts)) then
        s%surf3 = facts%surf3
      else if (own) then
        call surface3d_build(s%surf3, b%x, b%facets, err, lean=present(rows))
      end if
      if (allocated(err)) then
        err%message = "body '"//trim(b%name)//"': "//err%message
        return
      end if
      allocate(s%bary(3, n))
      s%bary = 0.0_wp
    else if (own .and. present(facts)) then
      ! (the whole polyline of a plane body no rank holds whole, from facts)
      s%surface = facts%surf2
    else if (own) then
      call surface_build(s%surface, b%x, b%loop_ptr, b%loop_idx, b%loop_closed, axisym, &
        axis_fraction*minval(b%spacing(1:b%ndim)), err)
      if (allocated(err)) return
    end if
    if (present(facts)) then
      s%lo = facts%lo(1:b%ndim) - rmax(1:b%ndim)
      s%hi = facts%hi(1:b%ndim) + rmax(1:b%ndim)
    else
      s%lo = minval(b%x, dim=2) - rmax(1:b%ndim)
      s%hi = maxval(b%x, dim=2) + rmax(1:b%ndim)
    end if
    if (b%ndim == 2 .and. own) call nts_build(s%buckets, s%surface)
    allocate(s%x_old(b%ndim, n), s%x_pred(b%ndim, n), s%fphys(b%ndim, n), &
      s%active(n), s%seg(n), s%xi(n), s%imass(n), s%gap(n), s%slip(n), &
      s%nrm(b%ndim, n), s%tng(b%ndim, n), s%share(n))
    allocate(s%near(n))
    s%near = .true.
    if (allocated(b%glob)) then
      s%x_ref = b%x(:, rows)
      s%rho = b%rho(:, rows)
      s%vol = b%vol(rows)
    else if (allocated(s%glob)) then
      s%x_ref = b%x(:, s%glob)
      s%rho = b%rho(:, s%glob)
      s%vol = b%vol(s%glob)
    else
      s%x_ref = b%x
      s%rho = b%rho
      s%vol = b%vol
    end if
    s%x_old = s%x_ref
    s%x_pred = s%x_ref
    s%kid = b%kid
    s%wshape = b%wshape
    s%bid = b%bid
    s%h = b%h(1:b%ndim)
    allocate(s%vel(b%ndim), s%shift(b%ndim))
    s%vel = 0.0_wp
    s%shift = 0.0_wp
    s%fphys = 0.0_wp
    s%active = .false.
    s%seg = 0
    s%xi = 0.0_wp
    s%gap = 0.0_wp
    s%nrm = 0.0_wp
    s%tng = 0.0_wp
    s%imass = 0.0_wp
    s%share = 0.0_wp
    ! a node whose velocity is prescribed in every component does not yield to contact:
    ! infinite mass in eq. (93) (a driven plate), so the other side takes the whole gap
    if (isolid > 0) then
      associate (sol => solids(isolid))
        do i = 1, n
          j = solid_node_place(sol, side_whole(s, i))
          if (j == 0) then
            call set_error(err, "body '"//trim(b%name)//"': particle "// &
              itoa(side_whole(s, i))//" of a contact side is not in the rank's region of "// &
              "its solid (an internal error of the set-up)")
            return
          end if
          s%imass(i) = 1.0_wp/sol%t%mass(j)
          if (all(sol%pres(:, j))) s%imass(i) = 0.0_wp
        end do
      end associate
    end if
  end subroutine side_init

  !> The number of particles of side s's whole body (side_t np_whole).
  pure integer function side_np_whole(s) result(n)
    type(side_t), intent(in) :: s
    n = s%np
    if (s%np_whole > 0) n = s%np_whole
  end function side_np_whole

  !> The number in the whole body of particle i of side s (side_t glob).
  elemental integer function side_whole(s, i) result(j)
    type(side_t), intent(in) :: s
    integer, intent(in) :: i
    j = i
    if (allocated(s%glob)) j = s%glob(i)
  end function side_whole

  !> Skipping far particles on slave side s: the Lipschitz constant of its positions in
  !! its coefficients, lip = |(max_j sum_I |N1_I(X_j)|, max_j sum_I |N2_I(X_j)|)| (the
  !! position table of eq. 65; 1 for interpolating element nodes), and every particle due
  !! at the first step. In 3D the three components share one shape function (the table
  !! has one row) and lip = max_j sum_I |N_I(X_j)| bounds |sum_I N_I (d_I - d'_I)| the
  !! same way, so the skipping stays exact (test_contact3d: the same forces without it).
  subroutine skip_far_init(s, solids)
    type(side_t), intent(inout) :: s
    type(solid_t), intent(in) :: solids(:)
    integer :: j
    real(wp) :: l(max_dim)
    if (s%isolid == 0) return
    associate (t => solids(s%isolid)%t)
      if (t%interpolating) then
        s%lip = 1.0_wp
      else
        ! (the side's particles' places in the solid: a region shell's on ranks)
        l = position_sums(t, [(solid_node_place(solids(s%isolid), side_whole(s, j)), &
          j = 1, s%np)])
        s%lip = norm2(l(:size(t%pn, 1)))
      end if
    end associate
    s%skip_far = .true.
    s%travel = 0.0_wp
    allocate(s%due(s%np), s%d_scr(solids(s%isolid)%t%dims%ndim, s%np))
    s%due = -1.0_wp
    if (allocated(s%cand)) then
      allocate(s%clear(s%np), s%x_pass(size(s%x_pred, 1), s%np))
      s%clear = 0.0_wp
      s%x_pass = s%x_pred
    end if
    ! (the coefficients at the set-up: zero; a solid on ranks has none yet, a shell)
    s%d_scr = 0.0_wp
    s%near = .true.
  end subroutine skip_far_init

  !> Self-contact candidates of side s: the particles at the ends of its surface segments,
  !! each with its reference-neighbour radius rex = self_radius x its largest support.
  subroutine self_candidates(s, self_radius)
    type(side_t), intent(inout) :: s
    real(wp), intent(in) :: self_radius
    logical, allocatable :: on(:)
    integer :: k, n, j
    allocate(on(s%np))
    on = .false.
    if (s%ndim == 3) then
      ! (the vertices of the closed triangle surface)
      do k = 1, s%surf3%nf
        call mark(s%surf3%tri(1, k))
        call mark(s%surf3%tri(2, k))
        call mark(s%surf3%tri(3, k))
      end do
      ! (the whole surface's count, also where the side holds a part of it)
      s%ncand = s%surf3%nv_whole
    else
      do k = 1, s%surface%nseg
        call mark(s%surface%i0(k))
        call mark(s%surface%i1(k))
      end do
      s%ncand = count_distinct([s%surface%i0, s%surface%i1])
    end if
    allocate(s%cand(count(on)), s%rex(s%np), s%flagged(s%np))
    s%flagged = .false.
    n = 0
    do j = 1, s%np
      s%rex(j) = self_radius*maxval(s%rho(:, j))
      if (.not. on(j)) cycle
      n = n + 1
      s%cand(n) = j
    end do

  contains

    !> Particle i of the body (a surface vertex) a candidate, where the side holds it (a
    !! side over a rank's region: its place there).
    subroutine mark(i)
      integer, intent(in) :: i
      integer :: j
      j = i
      if (allocated(s%glob)) j = sorted_place(s%glob, i)
      if (j > 0) on(j) = .true.
    end subroutine mark
  end subroutine self_candidates

  !> The number of distinct values in v.
  function count_distinct(v) result(n)
    integer, intent(in) :: v(:)
    integer :: n, k
    integer :: idx(size(v))
    real(wp) :: key(size(v))
    key = real(v, wp)
    call sort_index(key, idx)
    n = 0
    do k = 1, size(v)
      if (k > 1) then
        if (v(idx(k)) == v(idx(k - 1))) cycle
      end if
      n = n + 1
    end do
  end function count_distinct

  !> Median det(M) of a body at its own boundary particles (off the symmetry axis): about
  !! what a particle touching the surface sees; a threshold above it misses shallow
  !! penetrations.
  function surface_det_median(b, c) result(dmed)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    real(wp) :: dmed
    real(wp), allocatable :: dets(:)
    integer, allocatable :: idx(:)
    integer :: i, n
    allocate(dets(count(b%boundary)))
    n = 0
    do i = 1, b%np
      if (.not. b%boundary(i)) cycle
      n = n + 1
      dets(n) = cloud_det(c, b%x(:, i))
    end do
    dmed = 0.0_wp
    if (n == 0) return
    ! (a heap sort: the insertion sort this was took minutes on a surface of 10^5)
    allocate(idx(n))
    call sort_index(dets(1:n), idx)
    dmed = dets(idx((n + 1)/2))
  end function surface_det_median

  !> Contact corrections of pair p for the step dt: the coefficients d (predicted by eq. 64
  !! from d_old) and a_n of the deformable bodies in solids are corrected in place; the
  !! contact forces spread onto their nodes are added to their fcon (N).
  subroutine contact_correct(p, solids, dt, err)
    type(contact_pair_t), intent(inout) :: p
    type(solid_t), intent(inout) :: solids(:)
    real(wp), intent(in) :: dt
    type(error_t), allocatable, intent(inout) :: err
    integer :: sd
    if (allocated(p%dist)) then
      call dist_correct(p, solids, dt, err)
      return
    end if
    p%step = contact_stats_t()
    call side_select(p%side(1), solids)
    call side_select(p%side(2), solids)
    if (p%self) then
      call self_correct(p, solids, dt, err)
      return
    end if
    ! the slave's det(M) and surface are needed only when both bodies deform
    do sd = 1, 2
      if (p%side(sd)%skip_far) then
        call side_near_positions(p%side(sd), solids(p%side(sd)%isolid), p%side(3 - sd), &
          p%count%skipped)
        cycle
      end if
      ! only the master's cloud, surface and buckets are needed in this pass
      call side_positions(p%side(sd), solids, sd == 2, need_det(p), need_nts(p), err)
      if (allocated(err)) return
    end do
    call contact_pass(p, p%side(1), p%side(2), solids, dt, .true., err)
    if (allocated(err)) return
    if (p%both_ways) then
      ! eq. (28), second condition: the master's particles against the slave, whose
      ! cloud and surface now move to the corrected positions
      do sd = 1, 2
        call side_positions(p%side(sd), solids, sd == 1, need_det(p), need_nts(p), err)
        if (allocated(err)) return
      end do
      call contact_pass(p, p%side(2), p%side(1), solids, dt, .false., err)
    end if
    p%count%detected_max = max(p%count%detected_max, int(p%step%n_flagged, i64))
    p%count%cmp_det_max = max(p%count%cmp_det_max, int(p%step%n_cmp_det, i64))
    p%count%cmp_gap_max = max(p%count%cmp_gap_max, int(p%step%n_cmp_gap, i64))
  end subroutine contact_correct

  !> Self-contact corrections of pair p (one body, both sides views of it) for the step dt.
  !! Where two faces of the body meet, each face's particles penetrate the other face; a
  !! single pass over all of them would put back each penetration twice (once by the
  !! particle's own force, once by the reactions of the other face's particles). So, as
  !! for two bodies (eq. 28), two passes with the correction between them: the first takes
  !! as slave only a particle numbered below both ends of the segment it hit (in each
  !! contact zone one face is slave, the other master), the second every particle still
  !! penetrating after that correction.
  !!
  !! Skipping (&contact skip_far, exact): a candidate found at clearance c from the supports
  !! of its non-neighbours (cloud_clearance) cannot be covered by them before the bound on
  !! their relative motion since then, twice the bound on any particle's motion summed over
  !! the steps (side_near_positions), reaches c. A step with no candidate due does nothing
  !! (no positions, no re-binning); otherwise only the due candidates are evaluated, and
  !! the second pass is made only when the first flagged a candidate.
  subroutine self_correct(p, solids, dt, err)
    type(contact_pair_t), intent(inout) :: p
    type(solid_t), intent(inout) :: solids(:)
    real(wp), intent(in) :: dt
    type(error_t), allocatable, intent(inout) :: err
    logical :: due
    p%count%screened = p%count%screened + size(p%side(1)%cand)
    if (p%side(1)%skip_far) then
      call self_schedule(p, solids(p%side(1)%isolid), due)
      if (.not. due) return
    end if
    p%side(2)%near = p%side(1)%near
    call self_positions(p%side(1), p%side(2), solids, err)
    if (allocated(err)) return
    if (p%side(1)%skip_far) p%side(1)%x_pass = p%side(1)%x_pred
    call contact_pass(p, p%side(1), p%side(2), solids, dt, .true., err, lower_only=.true.)
    if (allocated(err)) return
    ! nothing flagged: the second pass would see the same positions and flag nothing
    if (p%step%n_flagged == 0) return
    call self_positions(p%side(2), p%side(1), solids, err)
    if (allocated(err)) return
    if (p%side(1)%skip_far) call self_settled(p%side(1), p%side(2))
    call contact_pass(p, p%side(2), p%side(1), solids, dt, .false., err)
    if (allocated(err)) return
    p%count%detected_max = max(p%count%detected_max, int(p%step%n_flagged, i64))
  end subroutine self_correct

  !> The second pass of a self-contact step screens only the candidates the first pass's
  !! correction may have brought under a non-neighbour's support: s (side 1) holds the
  !! first pass's clearances and positions, s2 (side 2) the second's positions. A candidate
  !! found at clearance c (cloud_clearance: the smallest max_k (|x_Ik - p_k| - rho_Ik) over
  !! its non-neighbours I) stays uncovered while each of it and them moved by less than c/2
  !! in every component: then its det(M) without the neighbours is 0 again, bit for bit,
  !! and it is not screened (s2%near false). Bound: the largest component of any particle's
  !! move between the passes (all of the body's particles are in the cloud), doubled, plus
  !! a few units in the last place of the coordinates for the rounding of the differences,
  !! and c less the relative skip_rounding as for the schedule.
  subroutine self_settled(s, s2)
    type(side_t), intent(in) :: s
    type(side_t), intent(inout) :: s2
    integer :: k, j, jj
    real(wp) :: v(2), bound
    ! (the particles the side looks at: all, or a rank's own, the largest over the ranks)
    v = 0.0_wp
    do jj = 1, s%nlist
      j = side_particle(s, jj)
      v(1) = max(v(1), maxval(abs(s2%x_pred(:, j) - s%x_pass(:, j))))
      v(2) = max(v(2), maxval(abs(s2%x_pred(:, j))))
    end do
    if (associated(s%ranks)) call s%ranks%max_real(v)
    bound = 2.0_wp*v(1) + 8.0_wp*spacing(v(2))
    do k = 1, size(s%cand)
      j = s%cand(k)
      if (.not. s2%near(j)) cycle
      if ((1.0_wp - skip_rounding)*s%clear(j) > bound) s2%near(j) = .false.
    end do
  end subroutine self_settled

  !> Predicted positions of a self-contact body for a pass: computed once for the slave view
  !! a, copied to the master view b, whose cloud moves to them. (The positions at the start
  !! of the step are needed only where a force acts: self_old_positions.) A 3D surface
  !! moves only when the pass flags a candidate (detect_self_3d: most steps flag none).
  subroutine self_positions(a, b, solids, err)
    type(side_t), intent(inout) :: a, b
    type(solid_t), intent(in) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    call solid_positions(solids(a%isolid), at_prediction, a%x_pred)
    b%x_pred = a%x_pred
    call cloud_move(b%cloud, b%x_pred, err)
    if (allocated(err)) return
    if (b%ndim == 3) then
      b%surf_stale = .true.
    else
      call surface_update(b%surface, b%x_pred, err)
    end if
  end subroutine self_positions

  !> For self-contact, the positions at the start of the step of a's active particles and of the
  !! ends of the segments they hit (the slip of eq. 90 is relative to the master point).
  subroutine self_old_positions(a, b, sol)
    type(side_t), intent(inout) :: a, b
    type(solid_t), intent(in) :: sol
    integer :: j, i0, i1, k
    do j = 1, a%np
      if (.not. a%active(j)) cycle
      call solid_point_position(sol, j, a%x_old(:, j), at_step_start)
      if (a%ndim == 3) then
        ! (the facet's three vertices)
        do k = 1, 3
          i0 = b%surf3%tri(k, a%seg(j))
          call solid_point_position(sol, i0, b%x_old(:, i0), at_step_start)
        end do
        cycle
      end if
      i0 = b%surface%i0(a%seg(j))
      i1 = b%surface%i1(a%seg(j))
      call solid_point_position(sol, i0, b%x_old(:, i0), at_step_start)
      call solid_point_position(sol, i1, b%x_old(:, i1), at_step_start)
    end do
  end subroutine self_old_positions

  !> Self-contact with skip_far, a step's schedule (self_correct): the travel of side 1,
  !! twice the bound on any particle's motion summed since t = 0 (one step adds
  !! lip max_I |d_I - d'_I|, side_near_positions; twice for two particles moving towards
  !! each other), and whether any candidate is due (due). When one is, the candidates due
  !! within the next self_lookahead steps (at this step's travel) are marked near, so that
  !! their dues fall together and the re-binning is not repeated for one particle every
  !! step; the others are counted skipped. On a rank's part of a distributed pair
  !! (contact_dist_sm: side 1's ranks associated, gl(j) particle j's node in the part
  !! solid sol, the side's list the rank's own particles, its candidates the own ones) the
  !! travel and "any due" are the whole body's, over the ranks, so that every candidate
  !! is screened at the steps the serial run screens it. Collective then.
  subroutine self_schedule(p, sol, due, gl)
    type(contact_pair_t), intent(inout) :: p
    type(solid_t), intent(in) :: sol
    logical, intent(out) :: due
    integer, intent(in), optional :: gl(:)
    integer :: k, ndue
    real(wp) :: step_travel, horizon, v(1)
    associate (s => p%side(1))
      step_travel = s%travel
      call add_travel(s, sol, 2.0_wp, gl)
      step_travel = s%travel - step_travel
      due = any(s%travel >= s%due(s%cand))
      if (associated(s%ranks)) then
        v = merge(1.0_wp, 0.0_wp, due)
        call s%ranks%max_real(v)
        due = v(1) > 0.0_wp
      end if
      if (.not. due) then
        p%count%skipped = p%count%skipped + size(s%cand)
        return
      end if
      horizon = s%travel + real(self_lookahead, wp)*step_travel
      ndue = 0
      do k = 1, size(s%cand)
        s%near(s%cand(k)) = horizon >= s%due(s%cand(k))
        if (s%near(s%cand(k))) ndue = ndue + 1
      end do
      p%count%skipped = p%count%skipped + (size(s%cand) - ndue)
    end associate
  end subroutine self_schedule

  !> Add to s%travel factor x lip x max_I |d_I - d'_I|, d' the coefficients at the last
  !! call (kept in s%d_scr): a bound on any particle's motion since then, times factor.
  !! gl (a rank's part of a distributed pair): each particle's node in sol, a part solid.
  !! On ranks the maximum is the whole body's: taken over the ranks here, or already by
  !! travels_at_once with the other pairs' (s%dmax2_all).
  subroutine add_travel(s, sol, factor, gl)
    type(side_t), intent(inout) :: s
    type(solid_t), intent(in) :: sol
    real(wp), intent(in) :: factor
    integer, intent(in), optional :: gl(:)
    real(wp) :: dmax2, v(1)
    if (s%dmax2_all >= 0.0_wp) then
      dmax2 = s%dmax2_all
      s%dmax2_all = -1.0_wp
    else
      dmax2 = travel_local(s, sol, gl)
      if (associated(s%ranks)) then
        ! (collective: the whole body's bound, the serial one)
        v = dmax2
        call s%ranks%max_real(v)
        dmax2 = v(1)
      end if
    end if
    s%travel = s%travel + factor*s%lip*sqrt(dmax2)
  end subroutine add_travel

  !> max_I |d_I - d'_I|^2 over the particles side s looks at (on ranks its own), d' the
  !! coefficients at the last call, which become d (s%d_scr). gl: as add_travel's.
  real(wp) function travel_local(s, sol, gl) result(dmax2)
    type(side_t), intent(inout) :: s
    type(solid_t), intent(in) :: sol
    integer, intent(in), optional :: gl(:)
    integer :: i, ii, n
    dmax2 = 0.0_wp
    ! (with subcycling a pass looks at the nodes being stepped only: each particle's motion
    ! is still counted in the calls between its screenings, which is what the bound needs)
    if (present(gl)) then
      !$omp parallel do default(none) shared(s, sol, gl) private(i, n) reduction(max: dmax2) &
      !$omp schedule(static)
      do ii = 1, s%nlist
        i = side_particle(s, ii)
        n = gl(i)
        dmax2 = max(dmax2, sum((sol%state%d(:, n) - s%d_scr(:, i))**2))
        s%d_scr(:, i) = sol%state%d(:, n)
      end do
      !$omp end parallel do
    else
      !$omp parallel do default(none) shared(s, sol) private(i) reduction(max: dmax2) &
      !$omp schedule(static)
      do ii = 1, s%nlist
        i = side_particle(s, ii)
        dmax2 = max(dmax2, sum((sol%state%d(:, i) - s%d_scr(:, i))**2))
        s%d_scr(:, i) = sol%state%d(:, i)
      end do
      !$omp end parallel do
    end if
  end function travel_local

  !> On ranks, the motion bounds of the pairs that skip (add_travel: a rigid master's slave,
  !! a self-contact) taken over the ranks in one reduction at the start of the contact
  !! phase. Taken pair by pair, each reduction makes the pairs take turns: where each rank
  !! screens the contact of another pair (two slabs on two walls, each on its ranks), a
  !! rank with nothing to screen in a pair waits at the next pair's reduction for the ranks
  !! that have. Only a pair whose slave no earlier pair of the step touches (as slave or
  !! master) reads its bound here: its coefficients are then the same at the step's start
  !! as when it screens, so the bound is the one it would take itself, the same numbers.
  !! A pair after one that corrects its solid (a tube on a floor and under a ram) reads it
  !! itself, after that correction: read before, the bound would miss the correction's
  !! motion and the skipping would no longer be exact. Serial runs (no ranks), or fewer
  !! than two such pairs: nothing done here. Collective.
  subroutine travels_at_once(pairs, solids)
    type(contact_pair_t), intent(inout) :: pairs(:)
    type(solid_t), intent(in) :: solids(:)
    real(wp) :: v(size(pairs))
    integer :: k, n
    class(rank_comm_t), pointer :: ranks
    n = 0
    ranks => null()
    do k = 1, size(pairs)
      if (.not. reads_first(pairs, k)) cycle
      n = n + 1
      ranks => pairs(k)%side(1)%ranks
    end do
    if (n < 2) return
    n = 0
    do k = 1, size(pairs)
      if (.not. reads_first(pairs, k)) cycle
      n = n + 1
      associate (s => pairs(k)%side(1))
        if (allocated(pairs(k)%dist)) then
          v(n) = travel_local(s, solids(s%isolid), pairs(k)%dist%side(1)%gl)
        else
          ! (the part's own nodes: what contact_correct's side_select gives)
          call side_select(s, solids)
          v(n) = travel_local(s, solids(s%isolid))
        end if
      end associate
    end do
    call ranks%max_real(v(1:n))
    n = 0
    do k = 1, size(pairs)
      if (.not. reads_first(pairs, k)) cycle
      n = n + 1
      pairs(k)%side(1)%dmax2_all = v(n)
    end do
  end subroutine travels_at_once

  !> Does pair k read its motion bound at the start of the contact phase (travels_at_once)?
  !! Its slave side skips (skip_far) on a rank's part (against a rigid master, or a
  !! self-contact), and no earlier pair has a side on its solid.
  pure logical function reads_first(pairs, k)
    type(contact_pair_t), intent(in) :: pairs(:)
    integer, intent(in) :: k
    integer :: j
    reads_first = pairs(k)%side(1)%skip_far .and. associated(pairs(k)%side(1)%ranks)
    if (.not. reads_first) return
    do j = 1, k - 1
      if (any(pairs(j)%side(:)%isolid == pairs(k)%side(1)%isolid)) reads_first = .false.
    end do
  end function reads_first

  !> skip_far's lip of side s over the whole body, on a rank's part sol: a rank's tables
  !! may hold the position rows of its region only (the 3D RKPM set-up), so from its own
  !! particles, the largest over the ranks (element nodes: 1, as set). Collective.
  subroutine lip_over_ranks(s, sol, ranks)
    type(side_t), intent(inout) :: s
    type(solid_t), intent(in) :: sol
    class(rank_comm_t), intent(inout) :: ranks
    real(wp) :: l(max_dim)
    if (sol%t%interpolating) return
    l = position_sums(sol%t, sol%part%own_n)
    call ranks%max_real(l)
    s%lip = norm2(l(:size(sol%t%pn, 1)))
  end subroutine lip_over_ranks

  !> The largest sum_I |N_I(X_j)| of each row of t's position table over the particles
  !! list (skip_far_init's lip).
  pure function position_sums(t, list) result(l)
    type(solid_tables_t), intent(in) :: t
    integer, intent(in) :: list(:)
    real(wp) :: l(max_dim)
    integer :: k, j, c
    l = 0.0_wp
    do k = 1, size(list)
      j = list(k)
      do c = 1, size(t%pn, 1)
        l(c) = max(l(c), sum(abs(t%pn(c, t%pptr(j):t%pptr(j + 1) - 1))))
      end do
    end do
  end function position_sums

  !> The pair evaluates det(M) of its masters: its detector is det(M), or it compares.
  pure logical function need_det(p)
    type(contact_pair_t), intent(in) :: p
    need_det = p%detector == detector_det_m .or. p%compare
  end function need_det

  !> The pair searches its masters' segment buckets: its detector is node-to-segment, or it
  !! compares.
  pure logical function need_nts(p)
    type(contact_pair_t), intent(in) :: p
    need_nts = p%detector == detector_nts .or. p%compare
  end function need_nts

  !> The deck's name of detector id.
  pure function detector_name(id) result(name)
    integer, intent(in) :: id
    character(len=:), allocatable :: name
    select case (id)
    case (detector_nts)
      name = 'node_to_segment'
    case default
      name = 'det_m'
    end select
  end function detector_name

  !> The contact corrections of every pair for the step dt ending at time t1 (s), between
  !! the prediction (64) and the forces (62), and what they did together: contacts, flags
  !! and mean normal force summed, radius and remaining penetration the largest, the
  !! tracked edge in contact in any pair.
  subroutine contact_step(pairs, solids, dt, t1, total, err)
    type(contact_pair_t), intent(inout) :: pairs(:)
    type(solid_t), intent(inout) :: solids(:)
    real(wp), intent(in) :: dt, t1
    type(contact_stats_t), intent(out) :: total
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    real(wp) :: t0
    ! (on ranks: the pairs' motion bounds in one reduction)
    call travels_at_once(pairs, solids)
    do k = 1, size(pairs)
      t0 = omp_get_wtime()
      ! a moving rigid master at the prediction's time
      if (pairs(k)%side(2)%moving) pairs(k)%side(2)%shift = pairs(k)%side(2)%vel*t1
      call contact_correct(pairs(k), solids, dt, err)
      pairs(k)%count%t_pair = pairs(k)%count%t_pair + (omp_get_wtime() - t0)
      ! (every call: the sub-steps of subcycling too; on ranks this rank's particles)
      call exact_merge(pairs(k)%count%w_friction_sum, pairs(k)%step%sums(6))
      pairs(k)%count%w_friction = exact_value(pairs(k)%count%w_friction_sum)
      if (allocated(err)) return
      total%n_contact = total%n_contact + pairs(k)%step%n_contact
      total%n_flagged = total%n_flagged + pairs(k)%step%n_flagged
      total%n_cmp_det = total%n_cmp_det + pairs(k)%step%n_cmp_det
      total%n_cmp_gap = total%n_cmp_gap + pairs(k)%step%n_cmp_gap
      total%force_normal = total%force_normal + pairs(k)%step%force_normal
      total%radius = max(total%radius, pairs(k)%step%radius)
      total%pen_before = max(total%pen_before, pairs(k)%step%pen_before)
      total%pen_after = max(total%pen_after, pairs(k)%step%pen_after)
      total%edge_in_contact = total%edge_in_contact .or. pairs(k)%step%edge_in_contact
    end do
  end subroutine contact_step

  !> Distributed memory (issue 12, doc/parallel.md): pair p, set up on the whole slave
  !! solid, narrowed to a rank's part of it: the slave side's particles become the part's
  !! local nodes nglob (global numbers, ascending) of solids(p%side(1)%isolid), a part
  !! solid (solid_set_owned); its passes then look at the part's own nodes only
  !! (side_select). Rigid masters only: every rank holds the whole rigid body. The tracked
  !! edge particle stays with the rank that owns it (0 on the others). ranks: the ranks
  !! (kept by pointer), over which skip_far's bound on the motion is taken (add_travel).
  !! The side's arrays may have been cut to nglob already (contact_pair_cut, before the
  !! part's rows were made, so that the whole side is gone before the split's peak).
  subroutine contact_pair_localize(p, nglob, solids, ranks, err)
    type(contact_pair_t), intent(inout) :: p
    integer, intent(in) :: nglob(:)
    type(solid_t), intent(in) :: solids(:)
    class(rank_comm_t), pointer, intent(in) :: ranks
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, e
    if (.not. p%side(1)%cut) call contact_pair_cut(p, nglob, err)
    if (allocated(err)) return
    associate (s => p%side(1), sol => solids(p%side(1)%isolid))
      s%imass = 1.0_wp/sol%t%mass
      where (all(sol%pres, dim=1)) s%imass = 0.0_wp
      if (allocated(s%due)) then
        ! (the coefficients at the last screening: the cut's, zero at the start as the
        ! part's d, or a checkpoint's, whose d the part reads later)
        if (.not. allocated(s%d_scr)) s%d_scr = sol%state%d
        if (associated(ranks)) call lip_over_ranks(s, sol, ranks)
      end if
      s%ranks => ranks
      if (allocated(s%list)) deallocate(s%list)
      e = 0
      if (p%edge > 0) then
        do k = 1, size(nglob)
          if (nglob(k) == p%edge .and. any(sol%part%own_n == k)) e = k
        end do
      end if
      p%edge = e
    end associate
  end subroutine contact_pair_localize

  !> The arrays over the slave side's particles of pair p (a rigid master's: see
  !! contact_pair_localize) cut to the part's local nodes nglob (global numbers,
  !! ascending), those over the whole solid freed; what needs the part solid is left to
  !! contact_pair_localize.
  subroutine contact_pair_cut(p, nglob, err)
    type(contact_pair_t), intent(inout) :: p
    integer, intent(in) :: nglob(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: at(:)
    if (p%both_ways .or. p%self .or. p%side(2)%isolid /= 0) then
      call set_error(err, "contact of '"//trim(p%side(1)%name)//"' on '"// &
        trim(p%side(2)%name)//"': a rank's part of a solid takes rigid masters only")
      return
    end if
    associate (s => p%side(1))
      if (allocated(s%glob)) then
        ! (the side holds the rank's region: nglob's places in it)
        call region_places(s, nglob, at, err)
        if (allocated(err)) return
      else
        at = nglob
      end if
      call side_cut(s, at)
    end associate
  end subroutine contact_pair_cut

  !> The places in slave side s's region (s%glob) of the particles nglob (numbers in the
  !! whole body, ascending): every one is in it, since a rank's region holds its part.
  subroutine region_places(s, nglob, at, err)
    type(side_t), intent(in) :: s
    integer, intent(in) :: nglob(:)
    integer, allocatable, intent(out) :: at(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, i, n
    allocate(at(size(nglob)))
    n = size(s%glob)
    i = 1
    do k = 1, size(nglob)
      do while (i <= n)
        if (s%glob(i) >= nglob(k)) exit
        i = i + 1
      end do
      if (i > n) then
        at(k) = 0
      else if (s%glob(i) /= nglob(k)) then
        at(k) = 0
      else
        at(k) = i
      end if
      if (at(k) == 0) then
        call set_error(err, "contact of '"//trim(s%name)//"': particle "//itoa(nglob(k))// &
          " of the rank's part is not in its region (an internal error of the set-up)")
        return
      end if
    end do
  end subroutine region_places

  !> Slave side s (a rigid master's) cut to its particles at(:) (places in its arrays);
  !! skip_far's schedule kept (zero, or a restart's, read for the region).
  subroutine side_cut(s, at)
    type(side_t), intent(inout) :: s
    integer, intent(in) :: at(:)
    call side_take(s, at, size(at))
    ! (the part's masses set them: contact_pair_localize)
    if (allocated(s%imass)) deallocate(s%imass)
    if (allocated(s%glob)) deallocate(s%glob)
    s%cut = .true.
  end subroutine side_cut

  !> Side s's arrays over its particles made n long: entries 1..size(at) from the
  !! particles at (places in the arrays now), the rest zero (not active, near, not
  !! flagged, due at once) for the ghosts a plan fills in (contact_dist_sm make_plan);
  !! s%glob is left to the caller. (side_cut, and a distributed pair's sides.)
  subroutine side_take(s, at, n)
    type(side_t), intent(inout) :: s
    integer, intent(in) :: at(:), n
    s%np = n
    call take_r2(s%x_old)
    call take_r2(s%x_pred)
    call take_r2(s%fphys)
    call take_r2(s%nrm)
    call take_r2(s%tng)
    call take_r2(s%x_ref)
    call take_r2(s%rho)
    call take_r2(s%d_scr)
    call take_r2(s%x_pass)
    call take_r2(s%bary)
    call take_r1(s%xi, 0.0_wp)
    call take_r1(s%gap, 0.0_wp)
    call take_r1(s%slip, 0.0_wp)
    call take_r1(s%share, 0.0_wp)
    call take_r1(s%imass, 0.0_wp)
    call take_r1(s%vol, 0.0_wp)
    call take_r1(s%due, -1.0_wp)
    call take_r1(s%clear, 0.0_wp)
    call take_r1(s%rex, 0.0_wp)
    call take_l1(s%active, .false.)
    call take_l1(s%near, .true.)
    call take_l1(s%flagged, .false.)
    if (allocated(s%seg)) call take_i1(s%seg, at, n, 0)

  contains

    subroutine take_r2(a)
      real(wp), allocatable, intent(inout) :: a(:, :)
      real(wp), allocatable :: t(:, :)
      if (.not. allocated(a)) return
      allocate(t(size(a, 1), n))
      t = 0.0_wp
      t(:, 1:size(at)) = a(:, at)
      call move_alloc(t, a)
    end subroutine take_r2

    subroutine take_r1(a, fill)
      real(wp), allocatable, intent(inout) :: a(:)
      real(wp), intent(in) :: fill
      real(wp), allocatable :: t(:)
      if (.not. allocated(a)) return
      allocate(t(n))
      t = fill
      t(1:size(at)) = a(at)
      call move_alloc(t, a)
    end subroutine take_r1

    subroutine take_l1(a, fill)
      logical, allocatable, intent(inout) :: a(:)
      logical, intent(in) :: fill
      logical, allocatable :: t(:)
      if (.not. allocated(a)) return
      allocate(t(n))
      t = fill
      t(1:size(at)) = a(at)
      call move_alloc(t, a)
    end subroutine take_l1
  end subroutine side_take

  !> a made n long: entries 1..size(at) from a(at), the rest fill.
  subroutine take_i1(a, at, n, fill)
    integer, allocatable, intent(inout) :: a(:)
    integer, intent(in) :: at(:), n, fill
    integer, allocatable :: t(:)
    allocate(t(n))
    t = fill
    t(1:size(at)) = a(at)
    call move_alloc(t, a)
  end subroutine take_i1

  !> The particles of side s that this step's passes look at: all of them, or with
  !! subcycling the solid's nodes of the rate being stepped (the only ones that move).
  subroutine side_select(s, solids)
    type(side_t), intent(inout) :: s
    type(solid_t), intent(in) :: solids(:)
    integer :: r
    s%listed = .false.
    s%nlist = s%np
    if (s%isolid == 0) return
    associate (sol => solids(s%isolid))
      if (sol%sub%rate < 0) then
        ! a rank's part of a solid (distributed memory): its own nodes
        if (sol%part%on) then
          if (.not. allocated(s%list)) allocate(s%list(s%np))
          s%listed = .true.
          s%nlist = size(sol%part%own_n)
          s%list(1:s%nlist) = sol%part%own_n
        end if
        return
      end if
      r = sol%sub%rate
      if (.not. allocated(s%list)) allocate(s%list(s%np))
      s%listed = .true.
      s%nlist = sol%sub%nptr(r + 1) - sol%sub%nptr(r)
      s%list(1:s%nlist) = sol%sub%nlist(sol%sub%nptr(r):sol%sub%nptr(r + 1) - 1)
    end associate
  end subroutine side_select

  !> Particle jj of the ones side s looks at (side_select).
  pure integer function side_particle(s, jj) result(j)
    type(side_t), intent(in) :: s
    integer, intent(in) :: jj
    j = jj
    if (s%listed) j = s%list(jj)
  end function side_particle

  !> Old and predicted physical positions of a side; a deformable side is re-binned and its
  !! surface moved to the prediction.
  subroutine side_positions(s, solids, move, with_det, with_nts, err)
    type(side_t), intent(inout) :: s
    type(solid_t), intent(in) :: solids(:)
    logical, intent(in) :: move      !< the side acts as a master: move its cloud and surface
    logical, intent(in) :: with_det  !< its det(M) is needed: move its cloud
    logical, intent(in) :: with_nts  !< its segment buckets are needed: re-sort them
    type(error_t), allocatable, intent(inout) :: err
    if (s%isolid == 0) return
    call solid_positions(solids(s%isolid), at_step_start, s%x_old)
    call solid_positions(solids(s%isolid), at_prediction, s%x_pred)
    if (.not. move) return
    if (with_det) call cloud_move(s%cloud, s%x_pred, err)
    if (allocated(err)) return
    if (s%ndim == 3) then
      call surface3d_update(s%surf3, s%x_pred)
      s%surf_stale = .false.
    else
      call surface_update(s%surface, s%x_pred, err)
      if (allocated(err)) return
      if (with_nts) call nts_update(s%buckets, s%surface)
    end if
    s%lo = minval(s%x_pred, dim=2) - s%cloud%rmax(1:size(s%lo))
    s%hi = maxval(s%x_pred, dim=2) + s%cloud%rmax(1:size(s%hi))
  end subroutine side_positions

  !> Old and predicted physical positions of the particles of slave side s that could be in
  !! master b's grown box (b rigid); the others keep stale positions outside the box and are
  !! counted in nskip. Exact: a particle last found at distance r outside the box moved at
  !! most lip max_I |d_I - d'_I| per step (d' the coefficients at the step before), so it
  !! is screened again once those bounds, summed (travel), reach r. A moving rigid master's
  !! box moves too: its own travel |v| t1 (the length of its shift) is added.
  subroutine side_near_positions(s, sol, b, nskip)
    type(side_t), intent(inout) :: s
    type(solid_t), intent(in) :: sol
    type(side_t), intent(in) :: b
    integer(i64), intent(inout) :: nskip
    integer :: j, jj
    integer(i64) :: nfar
    real(wp) :: r(size(s%x_pred, 1)), travel
    call add_travel(s, sol, 1.0_wp)
    travel = s%travel
    if (b%moving) travel = travel + norm2(b%shift)
    nfar = 0
    !$omp parallel do default(none) shared(s, sol, b, travel) private(r, j) &
    !$omp reduction(+: nfar) schedule(static)
    do jj = 1, s%nlist
      j = side_particle(s, jj)
      s%near(j) = travel >= s%due(j)
      if (.not. s%near(j)) then
        nfar = nfar + 1
        cycle
      end if
      call solid_point_position(sol, j, s%x_pred(:, j))
      call solid_point_position(sol, j, s%x_old(:, j), at_step_start)
      ! distance outside the box, less a relative 1e-9 for the rounding of the sums
      r = max(b%lo + b%shift - s%x_pred(:, j), s%x_pred(:, j) - b%hi - b%shift, 0.0_wp)
      s%due(j) = travel + (1.0_wp - skip_rounding)*norm2(r)
    end do
    !$omp end parallel do
    nskip = nskip + nfar
  end subroutine side_near_positions

  !> One detection-and-force pass of side a's particles against side b (b's detector,
  !! b's surface). count_stats: this pass feeds the step's statistics and counters.
  subroutine contact_pass(p, a, b, solids, dt, count_stats, err, lower_only)
    type(contact_pair_t), intent(inout) :: p
    type(side_t), intent(inout) :: a, b
    type(solid_t), intent(inout) :: solids(:)
    real(wp), intent(in) :: dt
    logical, intent(in) :: count_stats
    type(error_t), allocatable, intent(inout) :: err
    !> in self-contact, only particles numbered below both ends of the segment they hit
    logical, intent(in), optional :: lower_only
    integer :: j, jj, i0, i1
    integer(i64) :: neval, ndet, ncon
    real(wp) :: g, nrm(2), tng(2), xq(2)
    logical :: found
    real(wp) :: t0
    if (a%ndim == 3) then
      call contact_pass_3d(p, a, b, solids, dt, count_stats, err, lower_only)
      return
    end if
    ! detection: which of a's particles penetrate b, with gap, normal, segment, projection
    t0 = omp_get_wtime()
    if (p%self) then
      call detect_self(a, b, present(lower_only), neval, ndet)
    else
      select case (p%detector)
      case (detector_nts)
      call detect_node_to_segment(a, b, neval, ndet)
      case default
        call detect_det_m(a, b, neval, ndet)
      end select
    end if
    p%count%t_detect = p%count%t_detect + (omp_get_wtime() - t0)
    if (p%self) call self_old_positions(a, b, solids(a%isolid))
    if (p%compare) call compare_detectors(p, a, b)
    call pass_forces(p, a, b, dt, count_stats, neval, ndet, ncon)
    if (ncon == 0 .and. .not. spreads(a, solids)) return
    ! reactions on b at the ends of the segments hit (serial: few particles)
    if (b%isolid > 0) then
      b%fphys = 0.0_wp
      do jj = 1, a%nlist
        j = side_particle(a, jj)
        if (.not. a%active(j)) cycle
        i0 = b%surface%i0(a%seg(j))
        i1 = b%surface%i1(a%seg(j))
        b%fphys(:, i0) = b%fphys(:, i0) - (1.0_wp - a%xi(j))*a%fphys(:, j)
        b%fphys(:, i1) = b%fphys(:, i1) - a%xi(j)*a%fphys(:, j)
      end do
      call solid_add_point_forces(solids(b%isolid), b%fphys)
      ! (self-contact: one solid, corrected once below)
      if (b%isolid /= a%isolid) call solid_correct(solids(b%isolid), dt)
    end if
    if (spreads(a, solids)) call solids(a%isolid)%part%halo%nodes(a%fphys)
    call solid_add_point_forces(solids(a%isolid), a%fphys)
    call solid_correct(solids(a%isolid), dt)
    if (spreads(a, solids)) call solid_share_corrections(solids(a%isolid))
    ! penetration left after the correction (eq. 98 spreads the forces): the
    ! corrected positions of the particles that had a force (and of b's surface when it
    ! moves; its cloud is moved again before it is next used)
    if (b%isolid > 0) call side_positions(b, solids, .true., .false., need_nts(p), err)
    if (allocated(err)) return
    do jj = 1, a%nlist
      j = side_particle(a, jj)
      if (.not. a%active(j)) cycle
      call solid_point_position(solids(a%isolid), j, a%x_pred(:, j))
      if (p%self) then
        call surface_gap(b%surface, a%x_pred(:, j), a%rho(:, j), found, g, nrm, tng, &
          xr=b%x_ref, xc=a%x_ref(:, j), rex=a%rex(j), rexv=b%rex)
      else if (p%detector == detector_nts) then
        ! (b's frame in a fixed array: the expression was a heap temporary a particle)
        xq = a%x_pred(:, j) - b%shift
        call nts_gap(b%buckets, b%surface, xq, b%buckets%capture, found, g, nrm, tng)
      else
        xq = a%x_pred(:, j) - b%shift
        call surface_gap(b%surface, xq, a%rho(:, j), found, g, nrm, tng)
      end if
      if (found) p%step%pen_after = max(p%step%pen_after, -g)
    end do
  end subroutine contact_pass

  !> The forces of eqs. (93)-(96) at side a's particles that the detection marked active
  !! against side b (ncon of them), into a%fphys, with the pass's counters (neval
  !! evaluated, ndet flagged) and statistics (count_stats: the step's first pass).
  subroutine pass_forces(p, a, b, dt, count_stats, neval, ndet, ncon)
    type(contact_pair_t), intent(inout) :: p
    type(side_t), intent(inout) :: a, b
    real(wp), intent(in) :: dt
    logical, intent(in) :: count_stats
    integer(i64), intent(in) :: neval, ndet
    integer(i64), intent(out) :: ncon
    integer :: j, jj, i0, i1
    real(wp) :: g, nrm(2), tng(2), slip, fj(2), pen, rad, xi, invmb, meff
    real(wp) :: dxb(2), sgn, ft
    type(exact_sum_t) :: xs(stat_sums), xl(stat_sums)
    logical :: stick
    ! forces (eqs. 93-96) at the penetrating particles, whichever detector found them
    ncon = 0
    pen = 0.0_wp
    rad = 0.0_wp
    ! the step's first pass pushes the slave's particles, the second the master's (their
    ! forces act on the slave with the opposite sign)
    sgn = merge(1.0_wp, -1.0_wp, count_stats)
    ! shared effective mass: how much of each master node the particles load together (on
    ! ranks, route_shares has summed them over the ranks' slave particles)
    if (p%shared_mass .and. b%isolid > 0 .and. .not. allocated(p%dist)) then
      b%share = 0.0_wp
      do j = 1, a%np
        if (.not. a%active(j)) cycle
        i0 = b%surface%i0(a%seg(j))
        i1 = b%surface%i1(a%seg(j))
        b%share(i0) = b%share(i0) + (1.0_wp - a%xi(j))
        b%share(i1) = b%share(i1) + a%xi(j)
      end do
    end if
    !$omp parallel default(none) shared(a, b, dt, p, sgn, xs) &
    !$omp private(j, g, nrm, tng, slip, fj, stick, xi, i0, i1, invmb, meff, dxb, ft, xl) &
    !$omp reduction(+: ncon) reduction(max: pen, rad)
    xl = exact_sum_t()
    !$omp do schedule(static)
    do jj = 1, a%nlist
      j = side_particle(a, jj)
      a%fphys(:, j) = 0.0_wp
      if (.not. a%active(j)) cycle
      g = a%gap(j)
      nrm = a%nrm(:, j)
      tng = a%tng(:, j)
      xi = a%xi(j)
      ! the master point's motion over the step: the slip is relative to it
      i0 = b%surface%i0(a%seg(j))
      i1 = b%surface%i1(a%seg(j))
      dxb = (1.0_wp - xi)*(b%x_pred(:, i0) - b%x_old(:, i0)) + xi*(b%x_pred(:, i1) - &
        b%x_old(:, i1))
      if (b%moving) dxb = b%vel*dt   ! a moving rigid master (its x_pred, x_old stay)
      ! the master point's inverse mass (0 when rigid): alone, (1-xi)^2/m0 + xi^2/m1; shared,
      ! the row sum (1-xi) S0/m0 + xi S1/m1 with S the nodes' total loading weights
      invmb = 0.0_wp
      if (b%isolid > 0) then
        if (p%shared_mass) then
          invmb = (1.0_wp - xi)*b%share(i0)*b%imass(i0) + xi*b%share(i1)*b%imass(i1)
        else
          invmb = (1.0_wp - xi)**2*b%imass(i0) + xi**2*b%imass(i1)
        end if
      end if
      ! (0 when both are held by kinematic conditions: nothing can move)
      meff = 0.0_wp
      if (a%imass(j) + invmb > 0.0_wp) meff = 1.0_wp/(a%imass(j) + invmb)
      slip = dot_product(a%x_pred(:, j) - a%x_old(:, j) - dxb, tng)
      a%slip(j) = slip
      call contact_point_force(g, nrm, tng, slip, meff, dt, p%mu, fj, stick)
      a%fphys(:, j) = fj
      ncon = ncon + 1
      call exact_add(xl(1), dot_product(fj, a%nrm(:, j)))
      ft = dot_product(fj, a%tng(:, j))
      call exact_add(xl(2), abs(ft))
      ! friction work on the slip left after the correction (0 when it sticks)
      if (meff > 0.0_wp) call exact_add(xl(6), 0.5_wp*ft*(slip + 0.5_wp*dt*dt*ft/meff))
      call exact_add(xl(3), sgn*fj(1))
      call exact_add(xl(4), sgn*fj(2))
      pen = max(pen, -a%gap(j))
      rad = max(rad, a%x_pred(1, j))
    end do
    !$omp end do
    !$omp critical (pass_sums)
    call merge_sums(xs, xl)
    !$omp end critical (pass_sums)
    !$omp end parallel
    if (.not. p%self) p%count%screened = p%count%screened + a%nlist
    p%count%evaluated = p%count%evaluated + neval
    p%count%detected = p%count%detected + ndet
    p%count%contacts = p%count%contacts + ncon
    if (count_stats) then
      p%step%n_contact = int(ncon)
      p%step%n_flagged = int(ndet)
      p%step%sums = xs
      p%step%radius = rad
      p%step%pen_before = pen
      if (p%edge > 0) p%step%edge_in_contact = a%active(p%edge)
    else
      p%step%n_contact = p%step%n_contact + int(ncon)
      p%step%n_flagged = p%step%n_flagged + int(ndet)
      call merge_sums(p%step%sums, xs)
      p%step%radius = max(p%step%radius, rad)
      p%step%pen_before = max(p%step%pen_before, pen)
    end if
    call stats_values(p%step)
  end subroutine pass_forces

  !> a(k) = a(k) + b(k), exactly.
  pure subroutine merge_sums(a, b)
    type(exact_sum_t), intent(inout) :: a(:)
    type(exact_sum_t), intent(in) :: b(:)
    integer :: k
    do k = 1, size(a)
      call exact_merge(a(k), b(k))
    end do
  end subroutine merge_sums

  !> The step's forces and friction work from their exact sums (each rounded once).
  subroutine stats_values(c)
    type(contact_stats_t), intent(inout) :: c
    c%force_normal = 0.5_wp*exact_value(c%sums(1))
    c%force_tangential = 0.5_wp*exact_value(c%sums(2))
    c%force_slave = 0.5_wp*[exact_value(c%sums(3)), exact_value(c%sums(4)), &
      exact_value(c%sums(5))]
    c%w_friction = exact_value(c%sums(6))
  end subroutine stats_values

  !> The paper's detector (eqs. 25-28): a's particles in b's grown box with det(M_b) above
  !! the threshold at their predicted positions are flagged (ndet of neval evaluated); the
  !! flagged ones get the gap to b's closest segment within their support (eq. 89), and
  !! those with g < 0 are marked active with it.
  subroutine detect_det_m(a, b, neval, ndet)
    type(side_t), intent(inout) :: a
    type(side_t), intent(in) :: b
    integer(i64), intent(out) :: neval, ndet
    integer :: j, jj, jseg
    real(wp) :: det, g, nrm(2), tng(2), xi, xq(2)
    logical :: found
    neval = 0
    ndet = 0
    !$omp parallel do default(none) shared(a, b) &
    !$omp private(j, det, found, g, nrm, tng, jseg, xi, xq) reduction(+: neval, ndet) &
    !$omp schedule(static)
    do jj = 1, a%nlist
      j = side_particle(a, jj)
      a%active(j) = .false.
      if (.not. a%near(j)) cycle   ! skip_far: cannot have reached b's box
      ! (in b's reference frame when b is a moving rigid body; shift 0 otherwise)
      xq = a%x_pred(:, j) - b%shift
      if (any(xq < b%lo) .or. any(xq > b%hi)) cycle
      neval = neval + 1
      det = cloud_det(b%cloud, xq)
      if (.not. (det > b%threshold)) cycle
      ndet = ndet + 1
      call surface_gap(b%surface, xq, a%rho(:, j), found, g, nrm, tng, jseg, xi)
      if (.not. found .or. .not. (g < 0.0_wp)) cycle
      call mark_active(a, j, g, nrm, tng, jseg, xi)
    end do
    !$omp end parallel do
  end subroutine detect_det_m

  !> contact_pass for 3D bodies: one detection-and-force pass of side a's particles against
  !! side b, b's closed triangle surface giving the gap and the normal. The reactions on a
  !! deformable b go to the three vertices of the facet each particle hit, weighted by the
  !! barycentric coordinates of its closest point (the 3D form of the plane pass's (1 - xi,
  !! xi) on a segment's ends), so their sum is minus the particle's force and their moment
  !! about the closest point vanishes.
  !! Self-contact (both sides views of one body, self_correct): detect_self_3d, the
  !! reactions added to the one solid, corrected once with the particles' forces.
  subroutine contact_pass_3d(p, a, b, solids, dt, count_stats, err, lower_only)
    type(contact_pair_t), intent(inout) :: p
    type(side_t), intent(inout) :: a, b
    type(solid_t), intent(inout) :: solids(:)
    real(wp), intent(in) :: dt
    logical, intent(in) :: count_stats
    type(error_t), allocatable, intent(inout) :: err
    !> in self-contact, only particles numbered below the three vertices of the facet hit
    logical, intent(in), optional :: lower_only
    integer :: j, jj, k, i, jf
    integer(i64) :: neval, ndet, ncon, nunsure
    real(wp) :: g, nrm(3), bary(3), t0, xq(3)
    logical :: sure
    t0 = omp_get_wtime()
    if (p%self) then
      call detect_self_3d(a, b, present(lower_only), neval, ndet, nunsure)
      if (count_stats) p%count%self_unsure = p%count%self_unsure + nunsure
    else
      call detect_det_m_3d(a, b, neval, ndet)
    end if
    p%count%t_detect = p%count%t_detect + (omp_get_wtime() - t0)
    if (p%self) call self_old_positions(a, b, solids(a%isolid))
    call pass_forces_3d(p, a, b, dt, count_stats, neval, ndet, ncon)
    ! (a rank's part of an RKPM slave exchanges its ghosts' forces below, with or without
    ! contacts of its own: the other ranks' spread over its nodes)
    if (ncon == 0 .and. .not. spreads(a, solids)) return
    ! reactions on b at the vertices of the facets hit (serial: few particles)
    if (b%isolid > 0) then
      b%fphys = 0.0_wp
      do jj = 1, a%nlist
        j = side_particle(a, jj)
        if (.not. a%active(j)) cycle
        do k = 1, 3
          i = b%surf3%tri(k, a%seg(j))
          b%fphys(:, i) = b%fphys(:, i) - a%bary(k, j)*a%fphys(:, j)
        end do
      end do
      call solid_add_point_forces(solids(b%isolid), b%fphys)
      ! (self-contact: one solid, corrected once below)
      if (b%isolid /= a%isolid) call solid_correct(solids(b%isolid), dt)
    end if
    ! (on ranks, eq. 98 spreads the ghost particles' forces too, and the corrected ghost
    ! nodes come from their owners, as in the plane pass)
    if (spreads(a, solids)) call solids(a%isolid)%part%halo%nodes(a%fphys)
    call solid_add_point_forces(solids(a%isolid), a%fphys)
    call solid_correct(solids(a%isolid), dt)
    if (spreads(a, solids)) call solid_share_corrections(solids(a%isolid))
    ! penetration left after the correction (eq. 98 spreads the forces): the corrected
    ! positions of the particles that had a force (and b's surface when it moves)
    if (b%isolid > 0) call side_positions(b, solids, .true., .false., .false., err)
    if (allocated(err)) return
    do jj = 1, a%nlist
      j = side_particle(a, jj)
      if (.not. a%active(j)) cycle
      call solid_point_position(solids(a%isolid), j, a%x_pred(:, j))
      sure = .true.
      if (p%self) then
        call surface3d_gap(b%surf3, a%x_pred(:, j), g, nrm, jf, bary, xr=b%x_ref, &
          xc=a%x_ref(:, j), rex=a%rex(j), sure=sure, rexv=b%rex)
      else
        ! (b's frame in a fixed array: the expression was a heap temporary a particle)
        xq = a%x_pred(:, j) - b%shift
        call surface3d_gap(b%surf3, xq, g, nrm, jf, bary)
      end if
      if (jf > 0 .and. sure) p%step%pen_after = max(p%step%pen_after, -g)
    end do
  end subroutine contact_pass_3d

  !> detect_self for 3D bodies: a's candidates (the vertices of its surface facets) with
  !! det(M) of the same body (b's cloud) from the particles that are not their reference
  !! neighbours (beyond rex) above the threshold are flagged (ndet of neval evaluated); the
  !! flagged ones get the signed gap to the closest facet none of whose vertices is a
  !! reference neighbour, and those with g < 0 are marked active with it. lower_only (the
  !! first pass of self_correct): only a particle numbered below the facet's three vertices;
  !! the second pass takes the rest, not those the first put on the surface. b's surface is
  !! moved to the pass's positions only when a candidate is flagged (b%surf_stale).
  subroutine detect_self_3d(a, b, lower_only, neval, ndet, nunsure, gmax)
    type(side_t), intent(inout) :: a
    type(side_t), intent(inout) :: b
    logical, intent(in) :: lower_only
    !> evaluated, flagged, and flagged with g < 0 of a sign not sure (no contact)
    integer(i64), intent(out) :: neval, ndet, nunsure
    !> the largest |g| of the flagged particles (huge when one found no facet)
    real(wp), intent(out), optional :: gmax
    integer :: k, j, jf
    real(wp) :: det, g, nrm(3), bary(3), gm
    logical :: sure
    integer(i64) :: nu
    neval = 0
    ndet = 0
    nu = 0
    gm = 0.0_wp
    a%active = .false.
    !$omp parallel do default(none) shared(a, b, lower_only) private(j, det) &
    !$omp reduction(+: neval, ndet) schedule(dynamic, 16)
    do k = 1, size(a%cand)
      j = a%cand(k)
      a%flagged(j) = .false.
      if (.not. a%near(j)) cycle   ! skipping: no non-neighbour can reach it yet
      if (.not. lower_only) then
        if (b%active(j)) cycle     ! put on the surface by the first pass
      end if
      neval = neval + 1
      call self_det(a, b, j, det)
      if (.not. (det > b%threshold)) cycle
      ndet = ndet + 1
      a%flagged(j) = .true.
    end do
    !$omp end parallel do
    if (present(gmax)) gmax = gm
    nunsure = 0
    if (ndet == 0) return
    if (b%surf_stale) then
      call surface3d_update(b%surf3, b%x_pred)
      b%surf_stale = .false.
    end if
    !$omp parallel do default(none) shared(a, b, lower_only) &
    !$omp private(j, g, nrm, jf, bary, sure) reduction(+: nu) reduction(max: gm) &
    !$omp schedule(dynamic, 16)
    do k = 1, size(a%cand)
      j = a%cand(k)
      if (.not. a%flagged(j)) cycle
      call surface3d_gap(b%surf3, a%x_pred(:, j), g, nrm, jf, bary, xr=b%x_ref, &
        xc=a%x_ref(:, j), rex=a%rex(j), sure=sure, rexv=b%rex)
      gm = max(gm, merge(abs(g), huge(1.0_wp), jf > 0))
      if (jf == 0 .or. .not. (g < 0.0_wp)) cycle
      ! (a sign not sure: the closest point's edge or vertex has a facet among the
      ! particle's reference neighbours, and the particle may lie outside: no contact)
      if (.not. sure) then
        nu = nu + 1
        cycle
      end if
      if (lower_only) then
        ! (by the numbers in the whole body: a rank numbers its own particles first)
        if (side_whole(a, j) >= min(side_whole(b, b%surf3%tri(1, jf)), &
          side_whole(b, b%surf3%tri(2, jf)), side_whole(b, b%surf3%tri(3, jf)))) cycle
      end if
      call mark_active_3d(a, j, g, nrm, jf, bary)
    end do
    !$omp end parallel do
    nunsure = nu
    if (present(gmax)) gmax = gm
  end subroutine detect_self_3d

  !> detect_det_m for 3D bodies: a's particles in b's grown box with det(M_b) above the
  !! threshold at their predicted positions are flagged (ndet of neval evaluated); the
  !! flagged ones get the signed gap to b's closed triangle surface (surface3d_gap: the
  !! closest point over the facets, found through their bins, the sign from the
  !! pseudo-normal of the feature it lies on), and those with g < 0 are marked active with
  !! the outward normal, the facet and the barycentric coordinates of the closest point.
  subroutine detect_det_m_3d(a, b, neval, ndet, gmax)
    type(side_t), intent(inout) :: a
    type(side_t), intent(in) :: b
    integer(i64), intent(out) :: neval, ndet
    !> the largest |g| of the flagged particles (huge when one found no facet)
    real(wp), intent(out), optional :: gmax
    integer :: j, jj, jf
    real(wp) :: det, g, nrm(3), bary(3), xq(3), gm
    neval = 0
    ndet = 0
    gm = 0.0_wp
    !$omp parallel do default(none) shared(a, b) &
    !$omp private(j, det, g, nrm, jf, bary, xq) reduction(+: neval, ndet) &
    !$omp reduction(max: gm) schedule(static)
    do jj = 1, a%nlist
      j = side_particle(a, jj)
      a%active(j) = .false.
      if (.not. a%near(j)) cycle   ! skip_far: cannot have reached b's box
      ! (in b's reference frame when b is a moving rigid body; shift 0 otherwise)
      xq = a%x_pred(:, j) - b%shift
      if (any(xq < b%lo) .or. any(xq > b%hi)) cycle
      neval = neval + 1
      det = cloud_det(b%cloud, xq)
      if (.not. (det > b%threshold)) cycle
      ndet = ndet + 1
      call surface3d_gap(b%surf3, xq, g, nrm, jf, bary)
      gm = max(gm, merge(abs(g), huge(1.0_wp), jf > 0))
      if (jf == 0 .or. .not. (g < 0.0_wp)) cycle
      call mark_active_3d(a, j, g, nrm, jf, bary)
    end do
    !$omp end parallel do
    if (present(gmax)) gmax = gm
  end subroutine detect_det_m_3d

  !> pass_forces for 3D bodies: the forces of eqs. (93)-(96) at side a's particles marked
  !! active against side b (ncon of them), into a%fphys, with the same counters and
  !! statistics. The master point is the closest point, sum_k bary_k x_k over the facet's
  !! vertices; its motion over the step, its inverse mass (alone: sum_k bary_k^2 / m_k;
  !! shared: the row sum sum_k bary_k S_k / m_k, S_k the vertex's total loading weight)
  !! and the reactions use those weights. The slip (eq. 90) is the relative displacement
  !! of the step projected on the tangent plane; a%tng gets its direction and a%slip its
  !! length, so the friction force is f . tng (<= 0) as in the plane.
  subroutine pass_forces_3d(p, a, b, dt, count_stats, neval, ndet, ncon)
    type(contact_pair_t), intent(inout) :: p
    type(side_t), intent(inout) :: a, b
    real(wp), intent(in) :: dt
    logical, intent(in) :: count_stats
    integer(i64), intent(in) :: neval, ndet
    integer(i64), intent(out) :: ncon
    integer :: j, jj, k, i
    real(wp) :: nrm(3), fj(3), dxb(3), ds(3), pen, rad, sgn
    real(wp) :: invmb, meff, ft, sl
    type(exact_sum_t) :: xs(stat_sums), xl(stat_sums)
    logical :: stick
    ncon = 0
    pen = 0.0_wp
    rad = 0.0_wp
    ! the step's first pass pushes the slave's particles, the second the master's (their
    ! forces act on the slave with the opposite sign)
    sgn = merge(1.0_wp, -1.0_wp, count_stats)
    ! shared effective mass: how much of each master vertex the particles load together (on
    ! ranks, route_shares has summed them over the ranks' slave particles)
    if (p%shared_mass .and. b%isolid > 0 .and. .not. allocated(p%dist)) then
      b%share = 0.0_wp
      do j = 1, a%np
        if (.not. a%active(j)) cycle
        do k = 1, 3
          i = b%surf3%tri(k, a%seg(j))
          b%share(i) = b%share(i) + a%bary(k, j)
        end do
      end do
    end if
    !$omp parallel default(none) shared(a, b, dt, p, sgn, xs) &
    !$omp private(j, k, i, nrm, fj, stick, invmb, meff, dxb, ds, ft, sl, xl) &
    !$omp reduction(+: ncon) reduction(max: pen, rad)
    xl = exact_sum_t()
    !$omp do schedule(static)
    do jj = 1, a%nlist
      j = side_particle(a, jj)
      a%fphys(:, j) = 0.0_wp
      if (.not. a%active(j)) cycle
      nrm = a%nrm(:, j)
      ! the master point's motion over the step and its inverse mass (0 when rigid)
      dxb = 0.0_wp
      invmb = 0.0_wp
      do k = 1, 3
        i = b%surf3%tri(k, a%seg(j))
        dxb = dxb + a%bary(k, j)*(b%x_pred(:, i) - b%x_old(:, i))
        if (b%isolid == 0) cycle
        if (p%shared_mass) then
          invmb = invmb + a%bary(k, j)*b%share(i)*b%imass(i)
        else
          invmb = invmb + a%bary(k, j)**2*b%imass(i)
        end if
      end do
      if (b%moving) dxb = b%vel*dt   ! a moving rigid master (its x_pred, x_old stay)
      ! (0 when both are held by kinematic conditions: nothing can move)
      meff = 0.0_wp
      if (a%imass(j) + invmb > 0.0_wp) meff = 1.0_wp/(a%imass(j) + invmb)
      ! the step's relative displacement in the tangent plane: the slip of eq. (90)
      ds = a%x_pred(:, j) - a%x_old(:, j) - dxb
      ds = ds - dot_product(ds, nrm)*nrm
      sl = norm2(ds)
      a%slip(j) = sl
      a%tng(:, j) = 0.0_wp
      if (sl > 0.0_wp) a%tng(:, j) = ds/sl
      call contact_point_force_3d(a%gap(j), nrm, ds, meff, dt, p%mu, fj, stick)
      a%fphys(:, j) = fj
      ncon = ncon + 1
      call exact_add(xl(1), dot_product(fj, nrm))
      ft = dot_product(fj, a%tng(:, j))
      call exact_add(xl(2), abs(ft))
      ! friction work on the slip left after the correction (0 when it sticks)
      if (meff > 0.0_wp) call exact_add(xl(6), 0.5_wp*ft*(sl + 0.5_wp*dt*dt*ft/meff))
      call exact_add(xl(3), sgn*fj(1))
      call exact_add(xl(4), sgn*fj(2))
      call exact_add(xl(5), sgn*fj(3))
      pen = max(pen, -a%gap(j))
      rad = max(rad, a%x_pred(1, j))
    end do
    !$omp end do
    !$omp critical (pass_sums)
    call merge_sums(xs, xl)
    !$omp end critical (pass_sums)
    !$omp end parallel
    if (.not. p%self) p%count%screened = p%count%screened + a%nlist
    p%count%evaluated = p%count%evaluated + neval
    p%count%detected = p%count%detected + ndet
    p%count%contacts = p%count%contacts + ncon
    if (count_stats) then
      p%step%n_contact = int(ncon)
      p%step%n_flagged = int(ndet)
      p%step%sums = xs
      p%step%radius = rad
      p%step%pen_before = pen
      if (p%edge > 0) p%step%edge_in_contact = a%active(p%edge)
    else
      p%step%n_contact = p%step%n_contact + int(ncon)
      p%step%n_flagged = p%step%n_flagged + int(ndet)
      call merge_sums(p%step%sums, xs)
      p%step%radius = max(p%step%radius, rad)
      p%step%pen_before = max(p%step%pen_before, pen)
    end if
    call stats_values(p%step)
  end subroutine pass_forces_3d

  !> Self-contact detection (Sections 1 and 7): a's candidates (its surface particles) with
  !! det(M) of the same body (b's cloud), assembled only from the particles that are not
  !! their neighbours in the reference configuration (beyond rex), above the threshold are
  !! flagged (ndet of neval evaluated); the flagged ones get the gap to b's closest segment
  !! within their support whose ends are not reference neighbours either, and those with
  !! g < 0 are marked active with it. lower_only: only a particle numbered below both ends
  !! of its segment (self_correct's first pass). In the second pass (not lower_only) b's
  !! active flags are the first pass's: a particle put on the surface there is not taken
  !! again (its gap is round-off, |g| ~ 1e-17 m; what the reactions leave is caught next
  !! step), so no particle is counted or pushed twice in a step.
  subroutine detect_self(a, b, lower_only, neval, ndet)
    type(side_t), intent(inout) :: a
    type(side_t), intent(in) :: b
    logical, intent(in) :: lower_only
    integer(i64), intent(out) :: neval, ndet
    integer :: k, j, jseg
    real(wp) :: det, g, nrm(2), tng(2), xi
    logical :: found
    neval = 0
    ndet = 0
    a%active = .false.
    !$omp parallel do default(none) shared(a, b, lower_only) &
    !$omp private(j, det, found, g, nrm, tng, jseg, xi) reduction(+: neval, ndet) &
    !$omp schedule(dynamic, 16)
    do k = 1, size(a%cand)
      j = a%cand(k)
      if (.not. a%near(j)) cycle   ! skipping: no non-neighbour can reach it yet
      if (.not. lower_only) then
        if (b%active(j)) cycle     ! put on the surface by the first pass
      end if
      neval = neval + 1
      call self_det(a, b, j, det)
      if (.not. (det > b%threshold)) cycle
      ndet = ndet + 1
      call surface_gap(b%surface, a%x_pred(:, j), a%rho(:, j), found, g, nrm, tng, jseg, xi, &
        xr=b%x_ref, xc=a%x_ref(:, j), rex=a%rex(j), rexv=b%rex)
      if (.not. found .or. .not. (g < 0.0_wp)) cycle
      if (lower_only) then
        ! (by the numbers in the whole body: a rank numbers its own particles first)
        if (side_whole(a, j) >= min(side_whole(b, b%surface%i0(jseg)), &
          side_whole(b, b%surface%i1(jseg)))) cycle
      end if
      call mark_active(a, j, g, nrm, tng, jseg, xi)
    end do
    !$omp end parallel do
  end subroutine detect_self

  !> det(M) of self-contact pair p's body at its particles own (current positions, the
  !! prediction), assembled from the particles that are not the particle's neighbours in
  !! the reference configuration (detect_self): 0 away from any fold, above the threshold
  !! where faces of the body meet. own: every particle of a serial pair; a rank's own
  !! particles of a distributed one (ascending, by the body's global numbers; collective,
  !! from the rank's contact cloud: dist_self_det). Work for output only, done at snapshots.
  subroutine contact_self_det(p, solids, det, own, err)
    type(contact_pair_t), intent(inout) :: p
    type(solid_t), intent(in) :: solids(:)
    real(wp), allocatable, intent(out) :: det(:)
    integer, allocatable, intent(out) :: own(:)
    type(error_t), allocatable, intent(inout) :: err
    type(rk_cloud_t) :: c
    real(wp), allocatable :: x(:, :)
    integer :: j
    if (allocated(p%dist)) then
      call dist_self_det(p, solids, det, own, err)
      return
    end if
    own = [(j, j = 1, p%side(1)%np)]
    allocate(det(p%side(1)%np))
    allocate(x, source=p%side(1)%x_ref)
    call solid_positions(solids(p%side(1)%isolid), at_prediction, x)
    call cloud_init(c, x, p%side(1)%rho, p%side(1)%vol, p%side(1)%kid, p%side(1)%wshape, &
      p%side(1)%bid, p%side(1)%h, err)
    if (allocated(err)) return
    call cloud_set_reference(c, p%side(1)%x_ref, p%self_radius)
    !$omp parallel do default(none) shared(c, p, x, det) schedule(static)
    do j = 1, p%side(1)%np
      det(j) = cloud_det_excluding(c, x(:, j), p%side(1)%x_ref(:, j), p%side(1)%rex(j))
    end do
    !$omp end parallel do
  end subroutine contact_self_det

  !> The conventional detector (contact_nts_m): a's particles in b's grown box (neval) get
  !! the gap to b's closest segment from the segment buckets, within the buckets' capture
  !! distance; those with g < 0 are flagged (ndet) and marked active with it.
  subroutine detect_node_to_segment(a, b, neval, ndet)
    type(side_t), intent(inout) :: a
    type(side_t), intent(in) :: b
    integer(i64), intent(out) :: neval, ndet
    integer :: j, jj, jseg
    real(wp) :: g, nrm(2), tng(2), xi, xq(2)
    logical :: found
    neval = 0
    ndet = 0
    !$omp parallel do default(none) shared(a, b) &
    !$omp private(j, found, g, nrm, tng, jseg, xi, xq) reduction(+: neval, ndet) &
    !$omp schedule(static)
    do jj = 1, a%nlist
      j = side_particle(a, jj)
      a%active(j) = .false.
      if (.not. a%near(j)) cycle   ! skip_far: cannot have reached b's box
      xq = a%x_pred(:, j) - b%shift   ! (b's reference frame)
      if (any(xq < b%lo) .or. any(xq > b%hi)) cycle
      neval = neval + 1
      call nts_gap(b%buckets, b%surface, xq, b%buckets%capture, found, g, nrm, tng, jseg, xi)
      if (.not. found .or. .not. (g < 0.0_wp)) cycle
      ndet = ndet + 1
      call mark_active(a, j, g, nrm, tng, jseg, xi)
    end do
    !$omp end parallel do
  end subroutine detect_node_to_segment

  !> det M_self at candidate j of side a (det(M) of b's particles that are not j's reference
  !! neighbours, at j's predicted position) and, when skipping, when j is screened again
  !! (pass 1 keeps the schedule): next step if a non-neighbour covers it (det > 0), else once
  !! they may have closed its clearance (searched up to self_reach x rex: a lower bound
  !! capped there is still a bound, and the search costs the cube of its reach plus the
  !! largest support, at this reach about what det(M) does; less a relative 1e-9 for the
  !! rounding of the sums), kept in a%clear for the second pass (self_settled).
  !! Called for distinct j from the threads of detect_self(_3d).
  subroutine self_det(a, b, j, det)
    type(side_t), intent(inout) :: a
    type(side_t), intent(in) :: b
    integer, intent(in) :: j
    real(wp), intent(out) :: det
    det = cloud_det_excluding(b%cloud, a%x_pred(:, j), a%x_ref(:, j), a%rex(j))
    if (.not. a%skip_far) return
    a%clear(j) = 0.0_wp
    if (det == 0.0_wp) a%clear(j) = max(0.0_wp, cloud_clearance(b%cloud, a%x_pred(:, j), &
      a%x_ref(:, j), a%rex(j), self_reach*a%rex(j)))
    a%due(j) = a%travel + (1.0_wp - skip_rounding)*a%clear(j)
  end subroutine self_det

  !> Particle j of side a penetrates (3D): its gap, normal, facet and the barycentric
  !! coordinates of its closest point there.
  pure subroutine mark_active_3d(a, j, g, nrm, jf, bary)
    type(side_t), intent(inout) :: a
    integer, intent(in) :: j, jf
    real(wp), intent(in) :: g, nrm(3), bary(3)
    a%active(j) = .true.
    a%gap(j) = g
    a%nrm(:, j) = nrm
    a%seg(j) = jf
    a%bary(:, j) = bary
  end subroutine mark_active_3d

  pure subroutine mark_active(a, j, g, nrm, tng, jseg, xi)
    type(side_t), intent(inout) :: a
    integer, intent(in) :: j, jseg
    real(wp), intent(in) :: g, nrm(2), tng(2), xi
    a%active(j) = .true.
    a%gap(j) = g
    a%nrm(:, j) = nrm
    a%tng(:, j) = tng
    a%seg(j) = jseg
    a%xi(j) = xi
  end subroutine mark_active

  !> Both detectors at a's particles in b's grown box, for the counters only (&contact
  !! compare_detectors): det(M_b) > threshold against the gap to b's closest segment at
  !! any distance (g < 0). Where they disagree: det(M) flags a particle outside the surface
  !! (the buffer zone, with its gap recorded), or misses a penetrating one.
  !! The particles are those the pass looks at (side_select: a rank's own ones), the gaps'
  !! sum exact, so that the counters add up to the serial ones over the ranks.
  subroutine compare_detectors(p, a, b)
    type(contact_pair_t), intent(inout) :: p
    type(side_t), intent(in) :: a, b
    integer :: j, jj
    integer(i64) :: nd, ng, nbuf, nmiss
    real(wp) :: det, g, nrm(2), tng(2), gmax, xq(2)
    type(exact_sum_t) :: gsum, gall
    logical :: found, fd, fg
    nd = 0
    ng = 0
    nbuf = 0
    nmiss = 0
    gmax = 0.0_wp
    !$omp parallel default(none) shared(a, b, gall) &
    !$omp private(j, det, found, g, nrm, tng, fd, fg, xq, gsum) &
    !$omp reduction(+: nd, ng, nbuf, nmiss) reduction(max: gmax)
    gsum = exact_sum_t()
    !$omp do schedule(static)
    do jj = 1, a%nlist
      j = side_particle(a, jj)
      if (.not. a%near(j)) cycle   ! skip_far: cannot have reached b's box
      xq = a%x_pred(:, j) - b%shift   ! (b's reference frame)
      if (any(xq < b%lo) .or. any(xq > b%hi)) cycle
      det = cloud_det(b%cloud, xq)
      call nts_gap(b%buckets, b%surface, xq, huge(1.0_wp), found, g, nrm, tng)
      fd = det > b%threshold
      fg = found .and. g < 0.0_wp
      if (fd) nd = nd + 1
      if (fg) ng = ng + 1
      if (fd .and. .not. fg) then
        nbuf = nbuf + 1
        call exact_add(gsum, g)
        gmax = max(gmax, g)
      end if
      if (fg .and. .not. fd) nmiss = nmiss + 1
    end do
    !$omp end do
    !$omp critical (compare_gaps)
    call exact_merge(gall, gsum)
    !$omp end critical (compare_gaps)
    !$omp end parallel
    p%count%cmp_det = p%count%cmp_det + nd
    p%count%cmp_gap = p%count%cmp_gap + ng
    p%count%cmp_buffer = p%count%cmp_buffer + nbuf
    p%count%cmp_missed = p%count%cmp_missed + nmiss
    call exact_merge(p%count%buffer_gap_exact, gall)
    p%count%buffer_gap_sum = exact_value(p%count%buffer_gap_exact)
    p%count%buffer_gap_max = max(p%count%buffer_gap_max, gmax)
    p%step%n_cmp_det = p%step%n_cmp_det + int(nd)
    p%step%n_cmp_gap = p%step%n_cmp_gap + int(ng)
  end subroutine compare_detectors

  !> det(M) of the master and of the slave (built from the slave's current physical
  !! positions with its reference volumes and supports: the Lagrangian body) on the grid
  !! lo..hi with n points (x fastest), and det(M_master) at the slave's nodes (Figs. 9-10).
  !! Work for output only, done at snapshots when the deck asks.
  subroutine contact_det_fields(p, solids, lo, hi, n, det_m, det_s, det_m_at_slave, err)
    type(contact_pair_t), intent(in) :: p
    type(solid_t), intent(in) :: solids(:)
    real(wp), intent(in) :: lo(2), hi(2)
    integer, intent(in) :: n(2)
    real(wp), intent(out) :: det_m(:), det_s(:), det_m_at_slave(:)
    type(error_t), allocatable, intent(inout) :: err
    type(rk_cloud_t) :: cs, cm
    real(wp), allocatable :: xs(:, :)
    integer :: i, j, q
    real(wp) :: x(2)
    if (p%side(1)%ndim == 3) then
      call set_error(err, "the det(M) grid of contact of '"//trim(p%side(1)%name)// &
        "' on '"//trim(p%side(2)%name)//"' is a plane grid: not for 3D bodies")
      return
    end if
    call current_cloud(p%side(1), cs, xs)
    if (allocated(err)) return
    call current_cloud(p%side(2), cm)
    if (allocated(err)) return
    !$omp parallel do default(none) shared(cm, cs, lo, hi, n, det_m, det_s) private(i, q, x)
    do j = 1, n(2)
      do i = 1, n(1)
        q = i + (j - 1)*n(1)
        x = lo + (hi - lo)*[real(i - 1, wp)/real(n(1) - 1, wp), real(j - 1, wp)/real(n(2) - 1, wp)]
        det_m(q) = cloud_det(cm, x)
        det_s(q) = cloud_det(cs, x)
      end do
    end do
    !$omp end parallel do
    do j = 1, p%side(1)%np
      det_m_at_slave(j) = cloud_det(cm, xs(:, j))
    end do
  contains
    subroutine current_cloud(s, c, xc)
      type(side_t), intent(in) :: s
      type(rk_cloud_t), intent(out) :: c
      real(wp), allocatable, intent(out), optional :: xc(:, :)
      real(wp), allocatable :: x(:, :)
      integer :: i
      x = s%x_ref
      if (s%isolid > 0) call solid_positions(solids(s%isolid), at_prediction, x)
      ! a moving rigid master where its last step put it
      if (s%moving) then
        do i = 1, size(x, 2)
          x(:, i) = x(:, i) + s%shift
        end do
      end if
      call cloud_init(c, x, s%rho, s%vol, s%kid, s%wshape, s%bid, s%h, err)
      if (present(xc)) call move_alloc(x, xc)
    end subroutine current_cloud
  end subroutine contact_det_fields
  !> Whether side s is a rank's part of an RKPM solid, whose contact forces eq. (98) spreads
  !! over RK neighbours: then a pass exchanges, contacts or not (collective), the ghost
  !! particles' point forces before the spreading and the corrected ghost nodes after
  !! (doc/parallel.md). A serial solid and an element part exchange nothing here.
  logical function spreads(s, solids)
    type(side_t), intent(in) :: s
    type(solid_t), intent(in) :: solids(:)
    spreads = .false.
    if (s%isolid == 0) return
    spreads = associated(solids(s%isolid)%part%halo) .and. .not. solids(s%isolid)%t%interpolating
  end function spreads
end module contact_pair_m
