!> The ranks a dynamic run's solids are spread over, as the one driver (explicit_driver_m)
!! sees them: a serial run is the one-rank case, whose parts are its whole solids and whose
!! collectives leave every value as it is (serial_domain_t, here); the MPI build's
!! mpi_domain_t (library mfcd_parallel) splits each solid into the ranks' parts, and rank 0
!! gathers what output needs (doc/parallel.md). The driver never asks which it has.
!!
!! What the domain does for the driver: split the set-up's whole solids into this rank's
!! parts (and narrow the contact pairs to them); give rank 0 the whole solids and pairs
!! output needs (gathered, for a snapshot, a failure, a checkpoint and the summary); the
!! sizes of the whole solids; the measures of the first solid; reductions of the step's
!! contact statistics and of the pairs' counters; the
!! checkpoint (rank 0 writes the serial layout); a report at the end. Reductions of plain
!! values go through its communicator (rank_comm_m).
module run_domain_m
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use rank_comm_m, only: rank_comm_t, single_rank_t
  use deck_m, only: deck_t
  use body_m, only: body_t
  use solid_m, only: solid_t
  use decomposition_m, only: rcb_tree_t
  use contact_pair_m, only: contact_pair_t, contact_stats_t
  use body_measures_m, only: measures_t, body_measures
  use run_report_m, only: run_record_t, self_det_out
  use run_health_m, only: fail_key_size, fail_key_first
  use run_files_m, only: run_files_t, run_files_checkpoint
  use dynamic_output_m, only: snapshot_write
  implicit none
  private
  public :: run_domain_t, serial_domain_t, serial_domain_init

  type, abstract :: run_domain_t
    !> the ranks, for reductions (contact keeps a pointer too)
    class(rank_comm_t), pointer :: comm => null()
    !> this rank writes the output and the log (rank 0)
    logical :: root = .true.
    !> the times the state was gathered to rank 0 after the split (snapshots' det(M)
    !! fields, checkpoints, a failure, the summary; none on one rank)
    integer :: gathers = 0
    !> a restart's checkpoint (set before the split), and whether each part reads its own
    !! rows of the state from it in the split (else the set-up's solids read it whole)
    character(len=:), allocatable :: restart_from
    logical :: reads_parts = .false.
  contains
    procedure(split_i), deferred :: split
    procedure(whole_i), deferred :: whole
    procedure(pairs_i), deferred :: output_pairs
    procedure(count_i), deferred :: whole_nodes
    procedure(count_i), deferred :: whole_points
    procedure(measures_i), deferred :: measures
    procedure(stats_i), deferred :: contact_stats
    procedure(counters_i), deferred :: counters
    procedure(checkpoint_i), deferred :: checkpoint
    procedure(snapshot_i), deferred :: snapshot_solids
    procedure(bodies_rows_i), deferred :: bodies_rows
    procedure(finish_i), deferred :: finish
    procedure :: any_error => domain_any_error
    procedure :: agree_error => domain_agree_error
    procedure :: agree_failure => domain_agree_failure
  end type run_domain_t

  abstract interface
    !> The whole solids of the set-up (with restarted, the state a checkpoint held) become
    !! this rank's parts, cut by the set-up's bisection of each (trees: dynamic_setup_t's),
    !! and the pairs are narrowed to them.
    subroutine split_i(dom, solids, pairs, restarted, trees, err)
      import :: run_domain_t, solid_t, contact_pair_t, error_t, rcb_tree_t
      class(run_domain_t), intent(inout), target :: dom
      type(solid_t), allocatable, intent(inout), target :: solids(:)
      type(contact_pair_t), intent(inout) :: pairs(:)
      logical, intent(in) :: restarted
      type(rcb_tree_t), intent(in) :: trees(:)
      type(error_t), allocatable, intent(inout) :: err
    end subroutine split_i
    !> The whole solids, for output on the root rank (collective): with full, all a
    !! checkpoint holds; else what snapshots and measures need.
    !> The whole solids on rank 0 (the parts' owned state gathered into them; with full
    !! what a checkpoint holds besides the output's fields; with state = .false. not
    !! gathered: their sizes and tables only).
    function whole_i(dom, solids, full, state) result(w)
      import :: run_domain_t, solid_t
      class(run_domain_t), intent(inout), target :: dom
      type(solid_t), intent(inout), target :: solids(:)
      logical, intent(in) :: full
      logical, intent(in), optional :: state
      type(solid_t), pointer :: w(:)
    end function whole_i
    !> The pairs as output draws their det(M) fields from the whole solids (root rank).
    function pairs_i(dom, pairs) result(w)
      import :: run_domain_t, contact_pair_t
      class(run_domain_t), intent(inout), target :: dom
      type(contact_pair_t), intent(inout), target :: pairs(:)
      type(contact_pair_t), pointer :: w(:)
    end function pairs_i
    !> Nodes (points) of whole solid k.
    integer function count_i(dom, solids, k)
      import :: run_domain_t, solid_t
      class(run_domain_t), intent(in) :: dom
      type(solid_t), intent(in) :: solids(:)
      integer, intent(in) :: k
    end function count_i
    !> The measures of the whole solid whose part s is (collective).
    function measures_i(dom, s) result(m)
      import :: run_domain_t, solid_t, measures_t
      class(run_domain_t), intent(inout) :: dom
      type(solid_t), intent(inout) :: s
      type(measures_t) :: m
    end function measures_i
    !> The step's contact statistics over the ranks (collective).
    subroutine stats_i(dom, c, pairs)
      import :: run_domain_t, contact_stats_t, contact_pair_t
      class(run_domain_t), intent(inout) :: dom
      type(contact_stats_t), intent(inout) :: c
      type(contact_pair_t), intent(inout) :: pairs(:)
    end subroutine stats_i
    !> The pairs' counters over the ranks, for the summary or a checkpoint (collective);
    !! restore puts back each rank's own afterwards (a checkpoint during the run).
    subroutine counters_i(dom, pairs, restore)
      import :: run_domain_t, contact_pair_t
      class(run_domain_t), intent(inout) :: dom
      type(contact_pair_t), intent(inout) :: pairs(:)
      logical, intent(in) :: restore
    end subroutine counters_i
    !> A checkpoint of the state after step r%n, written by rank 0 in the serial layout
    !! (collective).
    subroutine checkpoint_i(dom, out, bodies, r, solids, pairs, t_loop, err)
      import :: run_domain_t, run_files_t, body_t, run_record_t, solid_t, &
        contact_pair_t, error_t, wp
      class(run_domain_t), intent(inout), target :: dom
      type(run_files_t), intent(inout) :: out
      type(body_t), intent(in) :: bodies(:)
      type(run_record_t), intent(in) :: r
      type(solid_t), intent(inout), target :: solids(:)
      type(contact_pair_t), intent(inout), target :: pairs(:)
      real(wp), intent(in) :: t_loop
      type(error_t), allocatable, intent(inout) :: err
    end subroutine checkpoint_i
    !> The end of the loop: what the ranks report (collective).
    !> The solids' datasets of snapshot lab in out's file, with pairs the det(M) of each
    !! self-contact's body too (self_det_out; on ranks collectively, each its part's rows).
    subroutine snapshot_i(dom, out, lab, r, solids, err, pairs)
      import :: run_domain_t, run_files_t, run_record_t, solid_t, error_t, contact_pair_t
      class(run_domain_t), intent(inout) :: dom
      type(run_files_t), intent(inout) :: out
      character(len=*), intent(in) :: lab
      type(run_record_t), intent(in) :: r
      type(solid_t), intent(inout) :: solids(:)
      type(error_t), allocatable, intent(inout) :: err
      type(contact_pair_t), intent(inout), optional :: pairs(:)
    end subroutine snapshot_i
    !> The rows of the bodies that the ranks hold as shares (body_t row0 > 0: mfcd_mpi's
    !! deformable bodies) into /bodies of out's file, which rank 0 opened and wrote the
    !! rest of (run_files_open); collective. A serial run's bodies are whole: nothing.
    subroutine bodies_rows_i(dom, out, bodies, err)
      import :: run_domain_t, run_files_t, body_t, error_t
      class(run_domain_t), intent(inout) :: dom
      type(run_files_t), intent(inout) :: out
      type(body_t), intent(in) :: bodies(:)
      type(error_t), allocatable, intent(inout) :: err
    end subroutine bodies_rows_i
    subroutine finish_i(dom, solids, pairs, r)
      import :: run_domain_t, solid_t, contact_pair_t, run_record_t
      class(run_domain_t), intent(inout) :: dom
      type(solid_t), intent(in) :: solids(:)
      type(contact_pair_t), intent(inout) :: pairs(:)
      type(run_record_t), intent(in) :: r
    end subroutine finish_i
  end interface

  !> One rank: the parts are the whole solids.
  type, extends(run_domain_t) :: serial_domain_t
    type(single_rank_t) :: one
  contains
    procedure :: split => serial_split
    procedure :: whole => serial_whole
    procedure :: output_pairs => serial_pairs
    procedure :: whole_nodes => serial_nodes
    procedure :: whole_points => serial_points
    procedure :: measures => serial_measures
    procedure :: contact_stats => serial_stats
    procedure :: counters => serial_counters
    procedure :: checkpoint => serial_checkpoint
    procedure :: snapshot_solids => serial_snapshot
    procedure :: bodies_rows => serial_bodies_rows
    procedure :: finish => serial_finish
  end type serial_domain_t

contains

  !> A serial run's domain (dom must stay where it is: its communicator is its own).
  subroutine serial_domain_init(dom)
    type(serial_domain_t), intent(inout), target :: dom
    dom%comm => dom%one
    dom%root = .true.
  end subroutine serial_domain_init

  !> An error on any rank is an error on every rank, of its kind (bad input or a failed
  !! run: the larger exit code); the others get a pointer to it.
  logical function domain_any_error(dom, err) result(yes)
    class(run_domain_t), intent(inout) :: dom
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: v(2)
    v = 0.0_wp
    if (allocated(err)) v = [1.0_wp, real(err%code, wp)]
    call dom%comm%max_real(v)
    yes = v(1) > 0.0_wp
    if (yes .and. .not. allocated(err)) call set_error(err, 'another rank failed (its '// &
      'message is on its standard error)', nint(v(2)))
  end function domain_any_error

  !> Every rank learns of an error on any rank (domain_any_error, for the exchange alone).
  subroutine domain_agree_error(dom, err)
    class(run_domain_t), intent(inout) :: dom
    type(error_t), allocatable, intent(inout) :: err
    if (dom%any_error(err)) continue
  end subroutine domain_agree_error

  !> A failure on any rank fails every rank, with the reason the serial run gives: of the
  !! ranks' failures the first in the serial run's order (the failure keys, run_health_m
  !! fail_key_first), whose numbers are those of the whole solids.
  subroutine domain_agree_failure(dom, r)
    class(run_domain_t), intent(inout) :: dom
    type(run_record_t), intent(inout) :: r
    integer :: first(1)
    real(wp) :: keys(fail_key_size, dom%comm%nranks)
    character(len=:), allocatable :: why
    if (dom%comm%nranks == 1) return
    first = merge(0, 1, r%failed)
    call dom%comm%min_int(first)
    if (first(1) == 1) return
    if (.not. r%failed) r%fail_key = huge(1.0_wp)
    call dom%comm%allgather_real(r%fail_key, keys)
    first = fail_key_first(keys) - 1
    why = ''
    if (dom%comm%me == first(1)) why = r%reason
    call dom%comm%bcast_text(first(1), why)
    r%failed = .true.
    r%reason = why
    r%fail_key = keys(:, first(1) + 1)
  end subroutine domain_agree_failure

  subroutine serial_split(dom, solids, pairs, restarted, trees, err)
    class(serial_domain_t), intent(inout), target :: dom
    type(solid_t), allocatable, intent(inout), target :: solids(:)
    type(contact_pair_t), intent(inout) :: pairs(:)
    logical, intent(in) :: restarted
    type(rcb_tree_t), intent(in) :: trees(:)
    type(error_t), allocatable, intent(inout) :: err
    ! one rank: each part is its whole solid, every pair sees it whole
    if (size(pairs) < 0 .or. allocated(err) .or. size(trees) < 0 .or. &
      .not. dom%root .or. .not. allocated(solids) .or. restarted) continue
  end subroutine serial_split

  function serial_whole(dom, solids, full, state) result(w)
    class(serial_domain_t), intent(inout), target :: dom
    type(solid_t), intent(inout), target :: solids(:)
    logical, intent(in) :: full
    logical, intent(in), optional :: state
    type(solid_t), pointer :: w(:)
    w => solids
    if (full .and. .not. dom%root .and. present(state)) continue
  end function serial_whole

  function serial_pairs(dom, pairs) result(w)
    class(serial_domain_t), intent(inout), target :: dom
    type(contact_pair_t), intent(inout), target :: pairs(:)
    type(contact_pair_t), pointer :: w(:)
    w => pairs
    if (.not. dom%root) continue
  end function serial_pairs

  integer function serial_nodes(dom, solids, k) result(n)
    class(serial_domain_t), intent(in) :: dom
    type(solid_t), intent(in) :: solids(:)
    integer, intent(in) :: k
    n = solids(k)%np
    if (.not. dom%root) continue
  end function serial_nodes

  integer function serial_points(dom, solids, k) result(n)
    class(serial_domain_t), intent(in) :: dom
    type(solid_t), intent(in) :: solids(:)
    integer, intent(in) :: k
    n = solids(k)%nq
    if (.not. dom%root) continue
  end function serial_points

  function serial_measures(dom, s) result(m)
    class(serial_domain_t), intent(inout) :: dom
    type(solid_t), intent(inout) :: s
    type(measures_t) :: m
    m = body_measures(s)
    if (.not. dom%root) continue
  end function serial_measures

  subroutine serial_stats(dom, c, pairs)
    class(serial_domain_t), intent(inout) :: dom
    type(contact_stats_t), intent(inout) :: c
    type(contact_pair_t), intent(inout) :: pairs(:)
    ! one rank's statistics and counters are the run's
    if (.not. dom%root .or. size(pairs) < 0 .or. c%n_contact < 0) continue
  end subroutine serial_stats

  subroutine serial_counters(dom, pairs, restore)
    class(serial_domain_t), intent(inout) :: dom
    type(contact_pair_t), intent(inout) :: pairs(:)
    logical, intent(in) :: restore
    if (.not. dom%root .or. size(pairs) < 0 .or. restore) continue
  end subroutine serial_counters

  subroutine serial_snapshot(dom, out, lab, r, solids, err, pairs)
    class(serial_domain_t), intent(inout) :: dom
    type(run_files_t), intent(inout) :: out
    character(len=*), intent(in) :: lab
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(inout) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    type(contact_pair_t), intent(inout), optional :: pairs(:)
    if (.not. dom%root) continue
    call snapshot_write(out%f, lab, r%t, r%n, solids, err)
    if (present(pairs) .and. .not. allocated(err)) call self_det_out(out%f, lab, pairs, &
      solids, err)
  end subroutine serial_snapshot

  subroutine serial_bodies_rows(dom, out, bodies, err)
    class(serial_domain_t), intent(inout) :: dom
    type(run_files_t), intent(inout) :: out
    type(body_t), intent(in) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    if (.not. dom%root .or. size(bodies) < 0 .or. len(out%f%path) < 0 .or. allocated(err)) &
      continue
  end subroutine serial_bodies_rows

  subroutine serial_checkpoint(dom, out, bodies, r, solids, pairs, t_loop, err)
    class(serial_domain_t), intent(inout), target :: dom
    type(run_files_t), intent(inout) :: out
    type(body_t), intent(in) :: bodies(:)
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(inout), target :: solids(:)
    type(contact_pair_t), intent(inout), target :: pairs(:)
    real(wp), intent(in) :: t_loop
    type(error_t), allocatable, intent(inout) :: err
    call run_files_checkpoint(out, bodies, r, solids, pairs, t_loop, err)
    if (.not. dom%root) continue
  end subroutine serial_checkpoint

  subroutine serial_finish(dom, solids, pairs, r)
    class(serial_domain_t), intent(inout) :: dom
    type(solid_t), intent(in) :: solids(:)
    type(contact_pair_t), intent(inout) :: pairs(:)
    type(run_record_t), intent(in) :: r
    if (.not. dom%root .or. size(solids) + size(pairs) < 0 .or. r%n < 0) continue
  end subroutine serial_finish
end module run_domain_m
