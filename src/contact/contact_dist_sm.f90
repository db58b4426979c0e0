!> Contact of a pair whose master deforms (or of a body with itself), on one rank of a
!! distributed run (issue 12; doc/parallel.md, "Contact without a second decomposition").
!!
!! Each rank detects the penetration of the slave particles it owns, with det(M) of the
!! master (eqs. 1-8, 25-28) assembled from its own master particles and its ghost master
!! particles: those of other ranks within the ghost width w of the box of its slave
!! particles. w is the reach contact needs, R = the largest of the master's supports and of
!! the slave's supports plus twice the segments' reach and a cell of the segment bins (the
!! gap of eq. 89 looks there for the closest segment), plus a margin. A master particle left
!! out at the refresh was farther than w from every slave particle of the rank in some
!! direction; after the slave particles moved by at most D_s and the master particles by at
!! most D_m (the largest displacements since the refresh, over the ranks) it is still
!! farther than w - D_s - D_m, so it cannot take part while D_s + D_m + R < w. When that
!! fails the rank refreshes: each rank sends its own master particles that lie in the other
!! ranks' grown slave boxes (an allgather of 8 numbers per rank for the boxes; the particles
!! go point to point to the ranks whose boxes overlap, no global search, no all-to-all).
!!
!! Bitwise the serial run: the cloud and the surface segments are binned on the cells the
!! serial run's bins over the whole master have (their corner and extent from a reduction),
!! so det(M) sums the same particles in the same order and the closest segment is searched
!! among the same candidates in the same order; the reactions on a master particle are sent
!! to its owner and summed there in the order of the slave particles, as the serial pass
!! sums them. The rest is the serial pass (contact_pair_m), over the rank's own particles.
!! A side's arrays hold the rank's particles only, its own first and then its ghosts
!! (dist_side_t), each with its number in the whole body (side_t glob): the records and
!! the order of the cloud go by those numbers, so nothing depends on the local numbering.
!! Self-contact: both sides are views of one body, the candidates the rank's own surface
!! particles, det(M) without the reference neighbours, the two passes of self_correct.
submodule (contact_pair_m) contact_dist_sm
  use neighbour_bins_m, only: bins_cell_size
  use sorting_m, only: sort_index, sorted_place
  implicit none

contains

  module procedure contact_pair_own
    character(len=:), allocatable :: what
    what = "contact of '"//trim(p%side(1)%name)//"' on '"//trim(p%side(2)%name)//"': "
    if (.not. p%both_ways) then
      call set_error(err, what//"the master is rigid: a rank's part takes it whole "// &
        "(contact_pair_localize)")
    else if (p%detector /= detector_det_m .or. p%compare) then
      call set_error(err, what//"detector: a deforming master is distributed with "// &
        "detector = 'det_m' only (and compare_detectors = .false.)")
    end if
    if (allocated(err)) return
    if (.not. allocated(p%dist)) allocate(p%dist)
    if (p%self) then
      ! self-contact: each rank's own surface particles are its candidates
      if (sd == 1 .and. p%side(1)%skip_far) p%side(2)%skip_far = .false.
      associate (s => p%side(sd))
        s%cand = pack(s%cand, owner(s%cand) == me)
        s%near = .true.
      end associate
      ! with skip_far side 2's ghost width covers the clearance search over every
      ! candidate of the body (dist_master; the largest over the ranks' own:
      ! contact_pair_distribute), so that each clearance, hence each schedule, is the
      ! serial one
      associate (s => p%side(1))
        if (sd == 1 .and. s%skip_far .and. size(s%cand) > 0) &
          p%dist%clear_reach = self_reach*maxval(s%rex(s%cand))
      end associate
    end if
    call own_side(p%side(sd), p%dist%side(sd))

  contains

    !> Side s's static partners and surface's facets kept (plane: the whole surface's; 3D:
    !! those with a vertex among the rank's own particles, own_facets), its arrays over the
    !! whole body (or the rank's region) cut to the rank's own particles (its first nown),
    !! their numbers in the whole body kept (glob).
    subroutine own_side(s, ds)
      type(side_t), intent(inout) :: s
      type(dist_side_t), intent(inout) :: ds
      integer :: i, k, kk, q, n, e
      integer, allocatable :: cnt(:), own(:), ownw(:)
      logical, allocatable :: isp(:)
      ! (own: their places in the side's arrays; ownw: their numbers in the whole body)
      own = pack([(i, i = 1, s%np)], owner == me)
      ownw = side_whole(s, own)
      ds%nown = size(own)
      ! a tracked slave particle: its place among the rank's own (0 on the other ranks)
      if (sd == 1 .and. p%edge > 0) p%edge = sorted_place(ownw, p%edge)
      ! the facets (segments) a rank's subset is taken from at a refresh
      if (s%ndim == 3) then
        call own_facets(s%surf3, ownw, ds, err)
        if (allocated(err)) return
        allocate(ds%glo(3), ds%ghi(3))
      else
        ds%full%nseg = s%surface%nseg
        ds%full%i0 = s%surface%i0
        ds%full%i1 = s%surface%i1
        allocate(ds%glo(2), ds%ghi(2))
      end if
      ds%rmax = s%cloud%rmax(1:size(s%lo))
      ! the side's cloud and surface over the whole body freed: the first plan makes the
      ! rank's (make_plan)
      s%cloud = rk_cloud_t()
      s%surf3 = surface3d_t()
      s%surface = master_surface_t()
      s%buckets = nts_buckets_t()
      ! static partners: the ranks owning the first end of a segment (the first vertex of
      ! a facet) whose other end (vertex) is an own particle (they sum the segment's
      ! midpoint and reach, the facet's edges), and the ranks owning the other ends of the
      ! segments whose first end is an own particle
      allocate(cnt(ds%nown + 1), isp(0:nranks - 1))
      cnt = 0
      isp = .false.
      do kk = 1, nfacet(ds)
        do e = 2, nvert(ds)
          k = sorted_place(ownw, vert(ds, kk, e))
          if (k > 0 .and. vown(ds, kk, 1) /= me) cnt(k + 1) = cnt(k + 1) + 1
          if (vown(ds, kk, 1) == me) isp(vown(ds, kk, e)) = .true.
        end do
      end do
      isp(me) = .false.
      ds%pq = pack([(q, q = 0, nranks - 1)], isp)
      allocate(ds%pptr(ds%nown + 1))
      ds%pptr(1) = 1
      do k = 1, ds%nown
        ds%pptr(k + 1) = ds%pptr(k) + cnt(k + 1)
      end do
      allocate(ds%prank(ds%pptr(ds%nown + 1) - 1))
      cnt = 0
      do kk = 1, nfacet(ds)
        do e = 2, nvert(ds)
          k = sorted_place(ownw, vert(ds, kk, e))
          q = vown(ds, kk, 1)
          if (k == 0 .or. q == me) cycle
          n = ds%pptr(k) + cnt(k + 1)
          ds%prank(n) = q
          cnt(k + 1) = cnt(k + 1) + 1
        end do
      end do
      ! the arrays cut (the ghosts come with the first plans)
      if (.not. allocated(s%glob)) s%np_whole = s%np
      call side_take(s, own, ds%nown)
      s%glob = ownw
      allocate(ds%owner(ds%nown))
      ds%owner = me
      if (allocated(s%cand)) then
        do k = 1, size(s%cand)
          s%cand(k) = sorted_place(own, s%cand(k))
        end do
      end if
      s%listed = .true.
      s%list = [(k, k = 1, ds%nown)]
      s%nlist = ds%nown
    end subroutine own_side

    !> The facets of the surface sf (its facets, vertices and partners: the whole surface,
    !! or the part near the rank's region, whose facets' and partners' numbers are the
    !! whole surface's: sf%fid) with a vertex among the own particles (their numbers ownw,
    !! ascending), in its order, with their vertices' ranks (vowner), and each own
    !! particle's facets among them (dist_side_t fid ...; surface-sized for the part, not
    !! for the body). A part without a partner of such a facet (the region did not reach
    !! a facet's vertices) is refused (err).
    subroutine own_facets(sf, ownw, ds, err)
      type(surface3d_t), intent(in) :: sf
      integer, intent(in) :: ownw(:)
      type(dist_side_t), intent(inout) :: ds
      type(error_t), allocatable, intent(inout) :: err
      integer :: m, e, n, k
      integer, allocatable :: c(:), fm(:)
      logical, allocatable :: mine(:)
      allocate(mine(sf%nf), c(size(ownw) + 1))
      c = 0
      do m = 1, sf%nf
        mine(m) = .false.
        do e = 1, 3
          k = sorted_place(ownw, sf%tri(e, m))
          if (k == 0) cycle
          mine(m) = .true.
          c(k + 1) = c(k + 1) + 1
        end do
      end do
      fm = pack([(m, m = 1, sf%nf)], mine)
      n = size(fm)
      ds%fid = fm
      if (allocated(sf%fid)) ds%fid = sf%fid(fm)
      allocate(ds%ftri(3, n), ds%fpart(3, n), ds%fown(3, n))
      do m = 1, n
        ds%ftri(:, m) = sf%tri(:, fm(m))
        ds%fpart(:, m) = sf%partner(:, fm(m))
        ds%fown(:, m) = vowner(sf%tv(:, fm(m)))
      end do
      if (any(ds%fpart == 0)) then
        call set_error(err, "the surface of '"//trim(p%side(sd)%name)//"': a facet at a rank's "// &
          "own particle without the facet across an edge (the rank's region of the body "// &
          "does not reach one facet beyond its particles): an error of the set-up")
        return
      end if
      ! (each own particle's facets: a CSR over the own particles, in the facets' order)
      allocate(ds%vfptr(size(ownw) + 1))
      ds%vfptr(1) = 1
      do k = 1, size(ownw)
        ds%vfptr(k + 1) = ds%vfptr(k) + c(k + 1)
      end do
      allocate(ds%vfac(ds%vfptr(size(ownw) + 1) - 1))
      c = 0
      do m = 1, n
        do e = 1, 3
          k = sorted_place(ownw, ds%ftri(e, m))
          if (k == 0) cycle
          ds%vfac(ds%vfptr(k) + c(k + 1)) = m
          c(k + 1) = c(k + 1) + 1
        end do
      end do
      ds%cell3 = sf%cell
      ds%nf_whole = sf%nf_whole
    end subroutine own_facets

    !> The rank owning end (vertex) e, from 1, of segment (facet) kk of the surface the
    !! rank keeps (nfacet).
    integer function vown(ds, kk, e)
      type(dist_side_t), intent(in) :: ds
      integer, intent(in) :: kk, e
      if (allocated(ds%fid)) then
        vown = ds%fown(e, kk)
      else
        vown = vowner(kk + (e - 1)*ds%full%nseg)
      end if
    end function vown
  end procedure contact_pair_own

  module procedure contact_pair_distribute
    integer :: sd
    real(wp) :: v(1)
    p%dist%comm => comm
    p%dist%margin = margin
    p%dist%refresh = refresh
    call part_side(p%side(1), p%dist%side(1), nglob1, solids(p%side(1)%isolid)%np)
    if (allocated(err)) return
    call part_side(p%side(2), p%dist%side(2), nglob2, solids(p%side(2)%isolid)%np)
    if (allocated(err)) return
    ! self-contact with skip_far (self_schedule, self_settled): the travel and the second
    ! pass's bound over the ranks (side 1's ranks), lip the largest over the whole body (a
    ! rank's tables may hold the position rows of its region only: the 3D RKPM set-up)
    if (p%self .and. p%side(1)%skip_far) then
      p%side(1)%ranks => comm
      call lip_over_ranks(p%side(1), solids(p%side(1)%isolid), comm)
      v = p%dist%clear_reach
      call comm%max_real(v)
      p%dist%clear_reach = v(1)
    end if
    ! the first plans: the static partners only (the first pass refreshes them)
    do sd = 1, 2
      call make_plan(p, sd, 3 - sd, -1.0_wp, err)
      if (allocated(err)) return
    end do

  contains

    !> Side s's own particles' nodes in its part solid (nglob: the part's nodes' global
    !! numbers, ascending; npart their count) and its work arrays.
    subroutine part_side(s, ds, nglob, npart)
      type(side_t), intent(inout) :: s
      type(dist_side_t), intent(inout) :: ds
      integer, intent(in) :: nglob(:), npart
      integer :: k
      allocate(ds%gl(ds%nown))
      do k = 1, ds%nown
        ds%gl(k) = sorted_place(nglob, s%glob(k))
      end do
      if (any(ds%gl == 0)) then
        call set_error(err, "contact of '"//trim(p%side(1)%name)//"' on '"// &
          trim(p%side(2)%name)//"': a particle of '"//trim(s%name)//"' owned by rank "// &
          itoa(comm%me)//" is not a node of its part")
        return
      end if
      allocate(ds%f(size(s%x_pred, 1), npart), ds%mptr(comm%nranks + 1), &
        ds%nptr(comm%nranks + 1))
      allocate(ds%sbuf(0), ds%rbuf(0))
    end subroutine part_side
  end procedure contact_pair_distribute

  module procedure contact_dist_report
    integer :: sd
    do sd = 1, 2
      associate (ds => p%dist%side(sd))
        nrefresh(sd) = ds%nrefresh
        ghosts(sd) = real(ds%nghost_sum, wp)/real(max(ds%npass, 1_i64), wp)
        held(sd) = ds%held
        whole(sd) = p%side(sd)%np_whole
        facets(sd) = 0
        if (allocated(ds%fid)) facets(sd) = size(ds%fid)
        nfw(sd) = ds%nf_whole
      end associate
    end do
  end procedure contact_dist_report

  module procedure dist_self_det
    integer(i64) :: nsum, npass
    integer :: k, j
    ! (the ghost counts of the log are the passes')
    nsum = p%dist%side(2)%nghost_sum
    npass = p%dist%side(2)%npass
    call dist_master(p, 2, 1, solids, .true., err)
    p%dist%side(2)%nghost_sum = nsum
    p%dist%side(2)%npass = npass
    if (allocated(err)) return
    ! (the own particles are the rank's first; own: their numbers in the whole body)
    own = p%side(1)%glob(1:p%dist%side(1)%nown)
    allocate(det(size(own)))
    !$omp parallel do default(none) shared(p, own, det) private(j) schedule(static)
    do k = 1, size(own)
      j = k
      det(k) = cloud_det_excluding(p%side(2)%cloud, p%side(1)%x_pred(:, j), &
        p%side(1)%x_ref(:, j), p%side(1)%rex(j))
    end do
    !$omp end parallel do
  end procedure dist_self_det

  module procedure dist_correct
    integer :: sd
    real(wp) :: v(1)
    logical :: due
    p%step = contact_stats_t()
    if (p%self) then
      ! (self_correct: every candidate counted screened; with skip_far a step with none
      ! due on any rank does nothing)
      p%count%screened = p%count%screened + size(p%side(1)%cand)
      if (p%side(1)%skip_far) then
        call self_schedule(p, solids(p%side(1)%isolid), due, p%dist%side(1)%gl)
        if (.not. due) return
        ! (the own particles, the first of both sides)
        p%side(2)%near(1:p%dist%side(1)%nown) = p%side(1)%near(1:p%dist%side(1)%nown)
      end if
    end if
    ! the own particles' positions at the step start (they do not change in the step)
    do sd = 1, 2
      call own_positions(p%side(sd), p%dist%side(sd), solids(p%side(sd)%isolid), &
        at_step_start)
    end do
    ! eq. (28): the slave's particles against the master, then the master's against the
    ! slave at the corrected positions (self-contact, self_correct: the first pass takes a
    ! particle numbered below both ends of the segment it hit, the second the rest)
    call dist_pass(p, 1, 2, solids, dt, .true., err)
    if (allocated(err)) return
    if (p%self) then
      ! self_correct: nothing flagged on any rank, the second pass would flag nothing
      v = real(p%step%n_flagged, wp)
      call p%dist%comm%max_real(v)
      if (v(1) == 0.0_wp) return
    end if
    call dist_pass(p, 2, 1, solids, dt, .false., err)
    if (allocated(err)) return
    p%count%detected_max = max(p%count%detected_max, int(p%step%n_flagged, i64))
  end procedure dist_correct

  !> One pass of the own particles of side ia against side ib, the master (contact_pass).
  !! Collective.
  subroutine dist_pass(p, ia, ib, solids, dt, count_stats, err)
    type(contact_pair_t), intent(inout), target :: p
    integer, intent(in) :: ia, ib
    type(solid_t), intent(inout) :: solids(:)
    real(wp), intent(in) :: dt
    logical, intent(in) :: count_stats
    type(error_t), allocatable, intent(inout) :: err
    integer :: jj, j
    integer(i64) :: neval, ndet, ncon, nunsure
    real(wp) :: t0, v(1), g, nrm(2), tng(2), gmax
    logical :: found
    call dist_master(p, ib, ia, solids, .true., err)
    if (allocated(err)) return
    if (p%self .and. p%side(1)%skip_far) then
      if (count_stats) then
        ! (self_correct: the first pass's positions, for the second's self_settled)
        do jj = 1, p%side(1)%nlist
          j = p%side(1)%list(jj)
          p%side(1)%x_pass(:, j) = p%side(1)%x_pred(:, j)
        end do
      else
        call self_settled(p%side(1), p%side(2))
      end if
    end if
    associate (a => p%side(ia), b => p%side(ib), da => p%dist%side(ia), &
      db => p%dist%side(ib))
      t0 = omp_get_wtime()
      if (p%self .and. a%ndim == 3) then
        ! (as below, with the check of the ghost width of the 3D detection)
        do
          call detect_self_3d(a, b, count_stats, neval, ndet, nunsure, gmax)
          if (dist_covered(p, ib, ia, gmax, .true., err)) exit
          if (allocated(err)) return
        end do
        if (count_stats) p%count%self_unsure = p%count%self_unsure + nunsure
      else if (p%self) then
        ! (the first pass is self_correct's lower_only pass; the candidates counted in
        ! dist_correct)
        call detect_self(a, b, count_stats, neval, ndet)
      else if (a%ndim == 3) then
        ! the closest facet of every flagged particle, and the facets around its features,
        ! must be among the rank's: else a wider refresh and the search again
        do
          call detect_det_m_3d(a, b, neval, ndet, gmax)
          if (dist_covered(p, ib, ia, gmax, .true., err)) exit
          if (allocated(err)) return
        end do
      else
        call detect_det_m(a, b, neval, ndet)
      end if
      p%count%t_detect = p%count%t_detect + (omp_get_wtime() - t0)
      ! (the positions at the step start, self_old_positions' in the serial pass, are there:
      ! the own particles' from dist_correct, the ghosts' from their owners)
      if (p%shared_mass) call route_shares(p, ia, ib)
      if (a%ndim == 3) then
        call pass_forces_3d(p, a, b, dt, count_stats, neval, ndet, ncon)
      else
        call pass_forces(p, a, b, dt, count_stats, neval, ndet, ncon)
      end if
      ! no contact on any rank: nothing to correct (as the serial pass)
      v = real(ncon, wp)
      call p%dist%comm%max_real(v)
      if (v(1) == 0.0_wp) return
      ! the reactions on the master particles, summed by their owners (eq. 98 or 99 on
      ! the master's nodes), then the slave's own forces
      call route_reactions(p, ia, ib)
      if (p%self) then
        ! one solid: the reactions added, corrected once with the forces below
        if (spreads(b, solids)) call solids(b%isolid)%part%halo%nodes(db%f)
        call solid_add_point_forces(solids(b%isolid), db%f)
      else
        call spread_correct(db, solids(b%isolid), dt)
      end if
      da%f = 0.0_wp
      do jj = 1, a%nlist
        j = a%list(jj)
        if (a%active(j)) da%f(:, da%gl(j)) = a%fphys(:, j)
      end do
      call spread_correct(da, solids(a%isolid), dt)
      ! penetration left after the correction, against the master's corrected surface
      call dist_master(p, ib, ia, solids, .false., err)
      if (allocated(err)) return
      if (a%ndim == 3) then
        call pen_after_3d(p, ia, ib, err)
        return
      end if
      do jj = 1, a%nlist
        j = a%list(jj)
        if (.not. a%active(j)) cycle
        if (p%self) then
          call surface_gap(b%surface, a%x_pred(:, j), a%rho(:, j), found, g, nrm, tng, &
            xr=b%x_ref, xc=a%x_ref(:, j), rex=a%rex(j), rexv=b%rex)
        else
          call surface_gap(b%surface, a%x_pred(:, j), a%rho(:, j), found, g, nrm, tng)
        end if
        if (found) p%step%pen_after = max(p%step%pen_after, -g)
      end do
    end associate
  end subroutine dist_pass

  !> The penetration left after the correction (3D): the gaps of side ia's own particles
  !! that had a force, against the master's corrected surface (contact_pass_3d's), with the
  !! same check of the ghost width as the detection's. Collective.
  subroutine pen_after_3d(p, ia, ib, err)
    type(contact_pair_t), intent(inout), target :: p
    integer, intent(in) :: ia, ib
    type(error_t), allocatable, intent(inout) :: err
    integer :: jj, j, jf
    real(wp) :: g, nrm(3), bary(3), gm, pen
    logical :: sure
    associate (a => p%side(ia), b => p%side(ib))
      do
        gm = 0.0_wp
        pen = 0.0_wp
        do jj = 1, a%nlist
          j = a%list(jj)
          if (.not. a%active(j)) cycle
          sure = .true.
          if (p%self) then
            call surface3d_gap(b%surf3, a%x_pred(:, j), g, nrm, jf, bary, xr=b%x_ref, &
              xc=a%x_ref(:, j), rex=a%rex(j), sure=sure, rexv=b%rex)
          else
            call surface3d_gap(b%surf3, a%x_pred(:, j), g, nrm, jf, bary)
          end if
          gm = max(gm, merge(abs(g), huge(1.0_wp), jf > 0))
          if (jf > 0 .and. sure) pen = max(pen, -g)
        end do
        if (dist_covered(p, ib, ia, gm, .false., err)) exit
        if (allocated(err)) return
      end do
      p%step%pen_after = max(p%step%pen_after, pen)
    end associate
  end subroutine pen_after_3d

  !> Does the ghost width of side ib (3D) cover the gap search of side ia's own particles,
  !! whose largest |g| on this rank is gmax? The closest point q of a particle at x lies
  !! within |g| of x; every facet the brute-force search compares with it there, and every
  !! facet around q's vertex or edge (their pseudo-normals), has its vertices within
  !! |g| + 2 dmax of x, so the rank holds them all while that radius, plus the motion since
  !! the refresh, stays below the ghost width (the same argument as det(M)'s support in
  !! dist_master). When it does not, on any rank, every rank refreshes with a width that
  !! covers it (kept for the later refreshes, gcov), its cloud and surface are moved, and
  !! the caller searches again (.false.). Collective.
  logical function dist_covered(p, ib, ia, gmax, with_det, err) result(ok)
    type(contact_pair_t), intent(inout), target :: p
    integer, intent(in) :: ib, ia
    real(wp), intent(in) :: gmax
    logical, intent(in) :: with_det
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: v(1), r
    integer :: k, nd
    associate (b => p%side(ib), db => p%dist%side(ib))
      v = gmax
      call p%dist%comm%max_real(v)
      ! (a particle that found no facet: the whole master, capped to stay finite)
      r = min(v(1), 1.0e30_wp) + 2.0_wp*db%dmax
      ok = r + db%moved < db%width .or. .not. p%dist%refresh
      if (ok) return
      db%gcov = max(db%gcov, r)
      call make_plan(p, ib, ia, max(db%width, r*(1.0_wp + p%dist%margin)), err)
      if (allocated(err)) return
      db%moved = 0.0_wp
      call exchange_positions(p, ib)
      nd = size(b%lo)
      if (with_det) then
        do k = 1, size(db%loc)
          db%xl(:, k) = b%x_pred(:, db%loc(k))
        end do
        call cloud_move(b%cloud, db%xl, err, db%glo(1:nd), db%ghi(1:nd))
        if (allocated(err)) return
      end if
      call surface3d_update(b%surf3, b%x_pred)
      b%surf_stale = .false.
    end associate
  end function dist_covered

  !> Point forces ds%f on the nodes of a side's part solid sol (own entries; the ghosts'
  !! from their owners when eq. 98 spreads them) added to the solid, a_n and the prediction
  !! corrected, the corrected ghost nodes from their owners.
  subroutine spread_correct(ds, sol, dt)
    type(dist_side_t), intent(inout) :: ds
    type(solid_t), intent(inout) :: sol
    real(wp), intent(in) :: dt
    if (associated(sol%part%halo) .and. .not. sol%t%interpolating) call sol%part%halo%nodes(ds%f)
    call solid_add_point_forces(sol, ds%f)
    call solid_correct(sol, dt)
    if (associated(sol%part%halo) .and. .not. sol%t%interpolating) &
      call solid_share_corrections(sol)
  end subroutine spread_correct

  !> Side ib made ready to be the master of side ia's own particles: the own positions of
  !! both sides now (those at the step start: dist_correct), the ghosts' (at the step start
  !! and now) from their owners, the extremes
  !! of the whole master (one reduction), a refresh of the ghosts when the margin is used
  !! up, and the rank's cloud (with_det) and surface binned on the whole master's cells.
  subroutine dist_master(p, ib, ia, solids, with_det, err)
    type(contact_pair_t), intent(inout), target :: p
    integer, intent(in) :: ib, ia
    type(solid_t), intent(in) :: solids(:)
    logical, intent(in) :: with_det
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: v(17), mlo(3), mhi(3), reach(3), cell(3), need, mid(3)
    integer :: k, kk, i0, i1, nd, im, e
    associate (a => p%side(ia), b => p%side(ib), da => p%dist%side(ia), &
      db => p%dist%side(ib))
      nd = size(b%lo)
      im = 5*nd
      ! (after a correction only the slave particles with a force are looked at again, as
      ! in the serial pass: only theirs are needed, and only their displacements count)
      call own_positions(a, da, solids(a%isolid), at_prediction, active_only=.not. with_det)
      call own_positions(b, db, solids(b%isolid), at_prediction)
      call exchange_positions(p, ib)
      ! the whole master's extremes; in the plane its segments' midpoints and reach (each
      ! segment by the owner of its first end), in 3D its longest facet edge (each facet by
      ! the owner of its first vertex); the largest displacements since the refresh
      ! (the rank's surface holds every facet, segment, whose first vertex, end, it owns:
      ! the static partners)
      v = -huge(1.0_wp)
      do k = 1, db%nown
        v(1:nd) = max(v(1:nd), -b%x_pred(:, k))
        v(nd + 1:2*nd) = max(v(nd + 1:2*nd), b%x_pred(:, k))
      end do
      if (nd == 3) then
        do kk = 1, b%surf3%nf
          if (b%surf3%tri(1, kk) > db%nown) cycle
          do e = 1, 3
            i0 = b%surf3%tri(e, kk)
            i1 = b%surf3%tri(modulo(e, 3) + 1, kk)
            v(7) = max(v(7), norm2(b%x_pred(:, i1) - b%x_pred(:, i0)))
          end do
        end do
      else
        do kk = 1, b%surface%nseg
          i0 = b%surface%i0(kk)
          if (i0 > db%nown) cycle
          i1 = b%surface%i1(kk)
          mid(1:2) = 0.5_wp*(b%x_pred(:, i0) + b%x_pred(:, i1))
          v(5:6) = max(v(5:6), -mid(1:2))
          v(7:8) = max(v(7:8), mid(1:2))
          v(9:10) = max(v(9:10), 0.5_wp*abs(b%x_pred(:, i1) - b%x_pred(:, i0)))
        end do
      end if
      ! (squared, then the root of the largest)
      v(im + 1:im + 2) = 0.0_wp
      if (db%width >= 0.0_wp) then
        do k = 1, db%nown
          v(im + 1) = max(v(im + 1), sum((b%x_pred(:, k) - db%xr_m(:, k))**2))
        end do
        do k = 1, da%nown
          if (.not. with_det) then
            if (.not. a%active(k)) cycle
          end if
          v(im + 2) = max(v(im + 2), sum((a%x_pred(:, k) - db%xr_s(:, k))**2))
        end do
      end if
      v(im + 1:im + 2) = sqrt(v(im + 1:im + 2))
      call p%dist%comm%max_real(v(1:im + 2))
      db%glo = -v(1:nd)
      db%ghi = v(nd + 1:2*nd)
      db%moved = v(im + 1) + v(im + 2)
      if (nd == 3) then
        ! the reach contact needs: det(M) takes the master particles within their support;
        ! the gap search the facets near a flagged particle: one within the support of a
        ! master particle is within 2 dmax of one of that particle's facets (the search's
        ! radius |g| + 2 dmax, dist_covered), or as far as a search has needed (gcov)
        db%dmax = max(v(7), 0.0_wp)
        need = max(maxval(db%rmax) + 2.0_wp*db%dmax, db%gcov)
        ! self-contact with skip_far: the clearance search (self_det) takes the particles
        ! whose support comes within clear_reach of a candidate
        if (p%self .and. a%skip_far) need = max(need, maxval(db%rmax) + p%dist%clear_reach)
      else
        mlo(1:2) = -v(5:6)
        mhi(1:2) = v(7:8)
        reach(1:2) = max(v(9:10), 0.0_wp)
        ! the reach contact needs: det(M) takes the master particles within their support;
        ! the gap (eq. 89) the segments with a midpoint in a cell within the slave
        ! particle's support and the reach (surface_gap), so ends within twice the reach
        ! and a cell
        cell(1:2) = bins_cell_size(mhi(1:2) - mlo(1:2), max(2.0_wp*reach(1:2), &
          tiny(1.0_wp)))
        need = maxval(max(db%rmax, da%rmax + 2.0_wp*reach(1:2) + cell(1:2)))
        if (p%self .and. a%skip_far) need = max(need, maxval(db%rmax) + p%dist%clear_reach)
      end if
      if (db%width < 0.0_wp .or. (p%dist%refresh .and. .not. (db%moved + need < &
        db%width))) then
        call make_plan(p, ib, ia, need*(1.0_wp + p%dist%margin), err)
        if (allocated(err)) return
        db%moved = 0.0_wp
        call exchange_positions(p, ib)
      end if
      if (with_det) then
        do k = 1, size(db%loc)
          db%xl(:, k) = b%x_pred(:, db%loc(k))
        end do
        call cloud_move(b%cloud, db%xl, err, db%glo, db%ghi)
        if (allocated(err)) return
      end if
      if (nd == 3 .and. p%self .and. with_det) then
        ! (self-contact: moved only when the pass flags a candidate, detect_self_3d)
        b%surf_stale = .true.
      else if (nd == 3) then
        call surface3d_update(b%surf3, b%x_pred)
        b%surf_stale = .false.
      else
        call surface_update(b%surface, b%x_pred, err, mlo(1:2), mhi(1:2), reach(1:2))
        if (allocated(err)) return
      end if
      b%lo = db%glo - b%cloud%rmax(1:nd)
      b%hi = db%ghi + b%cloud%rmax(1:nd)
      db%nghost_sum = db%nghost_sum + size(db%rids)
      db%npass = db%npass + 1
    end associate
  end subroutine dist_master

  !> Physical positions of side s's own particles (active_only: those with a contact force)
  !! at the step start (which = at_step_start, into x_old) or now (at_prediction, x_pred).
  subroutine own_positions(s, ds, sol, which, active_only)
    type(side_t), intent(inout) :: s
    type(dist_side_t), intent(in) :: ds
    type(solid_t), intent(in) :: sol
    integer, intent(in) :: which
    logical, intent(in), optional :: active_only
    integer :: k, i
    logical :: some
    some = .false.
    if (present(active_only)) some = active_only
    if (which == at_step_start) then
      !$omp parallel do default(none) shared(s, ds, sol) private(i) schedule(static)
      do k = 1, ds%nown
        i = k
        call solid_point_position(sol, ds%gl(i), s%x_old(:, i), at_step_start)
      end do
      !$omp end parallel do
    else if (sol%t%interpolating .and. .not. some) then
      ! (element nodes: X + d, as solid_point_position, without a call per node)
      !$omp parallel do default(none) shared(s, ds, sol) private(i) schedule(static)
      do k = 1, ds%nown
        i = k
        s%x_pred(:, i) = sol%x0(:, ds%gl(i)) + sol%state%d(:, ds%gl(i))
      end do
      !$omp end parallel do
    else
      !$omp parallel do default(none) shared(s, ds, sol, some) private(i) schedule(static)
      do k = 1, ds%nown
        i = k
        if (some) then
          if (.not. s%active(i)) cycle
        end if
        call solid_point_position(sol, ds%gl(i), s%x_pred(:, i))
      end do
      !$omp end parallel do
    end if
  end subroutine own_positions

  !> The ghosts' positions of side ib (at the step start and now) from their owners.
  subroutine exchange_positions(p, ib)
    type(contact_pair_t), intent(inout), target :: p
    integer, intent(in) :: ib
    integer :: k, m, nd, w
    associate (b => p%side(ib), db => p%dist%side(ib))
      nd = size(b%lo)
      w = 2*nd
      call ensure(db%sbuf, w*size(db%sids))
      do k = 1, size(db%sids)
        db%sbuf(w*(k - 1) + 1:w*k) = [b%x_old(:, db%sids(k)), b%x_pred(:, db%sids(k))]
      end do
      db%mptr(1:size(db%to) + 1) = w*(db%sptr - 1) + 1
      call p%dist%comm%sparse_exchange(db%to, db%mptr(1:size(db%to) + 1), db%sbuf, db%from, &
        db%nptr(1:size(db%from) + 1), db%rbuf)
      do m = 1, size(db%rids)
        b%x_old(:, db%rids(m)) = db%rbuf(w*(m - 1) + 1:w*(m - 1) + nd)
        b%x_pred(:, db%rids(m)) = db%rbuf(w*(m - 1) + nd + 1:w*m)
      end do
    end associate
  end subroutine exchange_positions

  !> The reactions of side ia's own active particles on the ends of the master segments
  !! (the vertices of the facets) they hit (eq. 98's point forces on side ib), each sent
  !! to the owner of its master particle, and summed there into db%f in the order of the
  !! slave particles, as the serial pass sums them.
  subroutine route_reactions(p, ia, ib)
    type(contact_pair_t), intent(inout), target :: p
    integer, intent(in) :: ia, ib
    integer :: nl, n0, n
    call route_to_owners(p, ia, ib, 2 + size(p%side(ib)%lo), .true., n0, n)
    associate (db => p%dist%side(ib))
      nl = db%nptr(size(db%to) + 1) - 1
      db%f = 0.0_wp
      call sum_records(db, db%sbuf(n0:n - 1), db%rbuf(1:nl), p%side(ib)%glob(1:db%nown))
    end associate
  end subroutine route_reactions

  !> The shared effective mass (pass_forces): for each master particle of the rank's cloud
  !! (own and ghosts), the sum S_i of the weights (1 - xi or xi) with which the active
  !! slave particles of every rank load it. The records (master particle, slave particle,
  !! weight) go to the owners of the segment ends, which sum them in the order of the
  !! slave particles (as the serial pass does: the same bits) and send the sums of their
  !! own particles along the ghost plan to the ranks that hold them as ghosts. Collective.
  subroutine route_shares(p, ia, ib)
    type(contact_pair_t), intent(inout), target :: p
    integer, intent(in) :: ia, ib
    integer :: k, i, m, nl, n0, n, nt, q
    call route_to_owners(p, ia, ib, 3, .false., n0, n)
    associate (b => p%side(ib), db => p%dist%side(ib))
      ! the owner's sums, in the order of the slave particles: the records (master, slave,
      ! weight), its own then the other ranks', sorted by slave particle
      nl = (n - n0)/3
      m = (db%nptr(size(db%to) + 1) - 1)/3
      nt = nl + m
      call ensure(db%wrec, 3*nt)
      call ensure(db%wkey, nt)
      if (allocated(db%widx)) then
        if (size(db%widx) < nt) deallocate(db%widx)
      end if
      if (.not. allocated(db%widx)) allocate(db%widx(max(nt, 1)))
      db%wrec(1:3*nl) = db%sbuf(n0:n - 1)
      db%wrec(3*nl + 1:3*nt) = db%rbuf(1:3*m)
      do k = 1, nt
        db%wkey(k) = db%wrec(3*k - 1)
      end do
      call sort_index(db%wkey(1:nt), db%widx(1:nt))
      b%share(1:db%nown) = 0.0_wp
      do k = 1, nt
        q = db%widx(k)
        i = sorted_place(b%glob(1:db%nown), nint(db%wrec(3*q - 2)))
        b%share(i) = b%share(i) + db%wrec(3*q)
      end do
      ! the ghosts' sums from their owners
      call ensure(db%sbuf, size(db%sids))
      db%sbuf(1:size(db%sids)) = b%share(db%sids)
      call p%dist%comm%sparse_exchange(db%to, db%sptr, db%sbuf(1:size(db%sids)), db%from, &
        db%nptr(1:size(db%from) + 1), db%rbuf)
      b%share(db%rids) = db%rbuf(1:size(db%rids))
    end associate
  end subroutine route_shares

  !> Records of width nw about the two segment ends (three facet vertices) of each own
  !! active particle of side ia, each sent to the owner of its master particle (back along
  !! the ghost plan, to the ranks the ghosts came from): for end e (from 0, master
  !! particle i) of slave particle j's segment (facet), (i, j, its share of j's force)
  !! when forces, else (i, j, the end's weight). On return the records this rank owns are
  !! db%sbuf(n0:n-1) (its own, in the order of its slave particles) and
  !! db%rbuf(1:db%nptr(size(db%to)+1)-1) (the other ranks'). Collective. (The record is
  !! chosen by a flag, not made by a procedure argument: an internal procedure passed as
  !! one needs an executable stack.)
  subroutine route_to_owners(p, ia, ib, nw, forces, n0, n)
    type(contact_pair_t), intent(inout), target :: p
    integer, intent(in) :: ia, ib, nw
    logical, intent(in) :: forces
    integer, intent(out) :: n0, n
    integer :: jj, j, e, i, q, k, nloc, nv
    integer :: slot(0:p%dist%comm%nranks - 1), cnt(size(p%dist%side(ib)%from))
    real(wp) :: rec(nw)
    associate (a => p%side(ia), db => p%dist%side(ib), me => p%dist%comm%me)
      nv = merge(3, 2, a%ndim == 3)
      slot = 0
      do k = 1, size(db%from)
        slot(db%from(k)) = k
      end do
      cnt = 0
      nloc = 0
      do jj = 1, a%nlist
        j = a%list(jj)
        if (.not. a%active(j)) cycle
        do e = 0, nv - 1
          q = db%owner(seg_end(j, e))
          if (q == me) then
            nloc = nloc + 1
          else
            cnt(slot(q)) = cnt(slot(q)) + 1
          end if
        end do
      end do
      db%mptr(1) = 1
      do k = 1, size(db%from)
        db%mptr(k + 1) = db%mptr(k) + nw*cnt(k)
      end do
      call ensure(db%sbuf, db%mptr(size(db%from) + 1) - 1 + nw*nloc)
      ! own master particles' records after the messages, in the same buffer
      n0 = db%mptr(size(db%from) + 1)
      n = n0
      cnt = 0
      do jj = 1, a%nlist
        j = a%list(jj)
        if (.not. a%active(j)) cycle
        do e = 0, nv - 1
          i = seg_end(j, e)
          ! (by the particles' numbers in the whole body)
          if (forces) then
            rec = [real(p%side(ib)%glob(i), wp), real(a%glob(j), wp), &
              end_weight(a, j, e)*a%fphys(:, j)]
          else
            rec = [real(p%side(ib)%glob(i), wp), real(a%glob(j), wp), end_weight(a, j, e)]
          end if
          q = db%owner(i)
          if (q == me) then
            db%sbuf(n:n + nw - 1) = rec
            n = n + nw
          else
            k = slot(q)
            db%sbuf(db%mptr(k) + nw*cnt(k):db%mptr(k) + nw*cnt(k) + nw - 1) = rec
            cnt(k) = cnt(k) + 1
          end if
        end do
      end do
      call p%dist%comm%sparse_exchange(db%from, db%mptr(1:size(db%from) + 1), db%sbuf, &
        db%to, db%nptr(1:size(db%to) + 1), db%rbuf)
    end associate

  contains

    !> End e (0: first, 1: second) of the master segment slave particle j hit (in 3D
    !! vertex e + 1 of the facet).
    integer function seg_end(j, e) result(i)
      integer, intent(in) :: j, e
      if (p%side(ia)%ndim == 3) then
        i = p%side(ib)%surf3%tri(e + 1, p%side(ia)%seg(j))
      else if (e == 0) then
        i = p%side(ib)%surface%i0(p%side(ia)%seg(j))
      else
        i = p%side(ib)%surface%i1(p%side(ia)%seg(j))
      end if
    end function seg_end
  end subroutine route_to_owners

  !> The records (master particle, slave particle, force; numbers in the whole body) of rl
  !! and rr subtracted into ds%f in the order of the slave particles (per master particle
  !! the serial order); own: the numbers of the rank's own master particles.
  subroutine sum_records(ds, rl, rr, own)
    type(dist_side_t), intent(inout) :: ds
    real(wp), intent(in) :: rl(:), rr(:)
    integer, intent(in) :: own(:)
    real(wp) :: key(size(rl)/(2 + size(ds%f, 1)) + size(rr)/(2 + size(ds%f, 1)))
    real(wp) :: rec(2 + size(ds%f, 1), size(key))
    integer :: idx(size(key)), k, m, nl, nw
    nw = 2 + size(ds%f, 1)
    nl = size(rl)/nw
    rec(:, 1:nl) = reshape(rl, [nw, nl])
    rec(:, nl + 1:) = reshape(rr, [nw, size(rr)/nw])
    key = rec(2, :)
    call sort_index(key, idx)
    do k = 1, size(idx)
      m = ds%gl(sorted_place(own, nint(rec(1, idx(k)))))
      ds%f(:, m) = ds%f(:, m) - rec(3:nw, idx(k))
    end do
  end subroutine sum_records

  !> The weight of end (vertex) e, from 0, of the segment (facet) slave particle j of side
  !! a hit: 1 - xi and xi in the plane, the barycentric coordinates in 3D.
  pure real(wp) function end_weight(a, j, e) result(w)
    type(side_t), intent(in) :: a
    integer, intent(in) :: j, e
    if (a%ndim == 3) then
      w = a%bary(e + 1, j)
    else
      w = a%xi(j)
      if (e == 0) w = 1.0_wp - w
    end if
  end function end_weight

  !> The number of segments of the whole surface ds%full (plane), of the facets with a
  !! vertex among the rank's own particles (3D: dist_side_t fid).
  pure integer function nfacet(ds)
    type(dist_side_t), intent(in) :: ds
    if (allocated(ds%fid)) then
      nfacet = size(ds%fid)
    else
      nfacet = ds%full%nseg
    end if
  end function nfacet

  !> Ends of a segment (2), vertices of a facet (3).
  pure integer function nvert(ds)
    type(dist_side_t), intent(in) :: ds
    nvert = merge(3, 2, allocated(ds%fid))
  end function nvert

  !> End (vertex) e, from 1, of segment (facet) kk of nfacet's.
  pure integer function vert(ds, kk, e) result(i)
    type(dist_side_t), intent(in) :: ds
    integer, intent(in) :: kk, e
    if (allocated(ds%fid)) then
      i = ds%ftri(e, kk)
    else if (e == 1) then
      i = ds%full%i0(kk)
    else
      i = ds%full%i1(kk)
    end if
  end function vert

  !> A new ghost plan of side ib as the master of side ia's own particles, for the ghost
  !! width w (< 0: the static partners only), with the rank's cloud and surface of its own
  !! and ghost particles. The ghosts arrive with their numbers in the whole body, reference
  !! positions, supports, volumes, inverse masses (self-contact: neighbour radii) and
  !! positions; side ib's arrays are remade over its own particles (kept in place) and the
  !! new ghosts, ascending by their numbers. Collective.
  subroutine make_plan(p, ib, ia, w, err)
    type(contact_pair_t), intent(inout), target :: p
    integer, intent(in) :: ib, ia
    real(wp), intent(in) :: w
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: mine(:), boxes(:, :), grown(:), key(:)
    integer :: q, k, i, n, nto, nfrom, me, nr, nd, m, nw, ng, nown, r
    logical :: dyn, take, rx
    integer, allocatable :: to(:), sptr(:), sids(:), from(:), ord(:), src(:), num0(:), &
      num1(:), gid(:)
    associate (a => p%side(ia), b => p%side(ib), da => p%dist%side(ia), &
      db => p%dist%side(ib), comm => p%dist%comm)
      me = comm%me
      nr = comm%nranks
      nd = size(b%lo)
      nown = db%nown
      ! the boxes of every rank's own slave and own master particles (lo, hi each)
      allocate(mine(4*nd), boxes(4*nd, 0:nr - 1), grown(2*nd))
      boxes = 0.0_wp
      if (w >= 0.0_wp) then
        mine = [box_of(a%x_pred, da%nown), box_of(b%x_pred, nown)]
        call comm%allgather_real(mine, boxes)
      end if
      ! what this rank sends: to rank q, its own master particles in q's slave box grown
      ! by w, and the partners q needs
      allocate(to(nr), sptr(nr + 1), sids(nown*min(nr, 8)))
      nto = 0
      sptr(1) = 1
      n = 0
      do q = 0, nr - 1
        if (q == me) cycle
        grown = [boxes(1:nd, q) - w, boxes(nd + 1:2*nd, q) + w]
        dyn = w >= 0.0_wp .and. overlap(boxes(2*nd + 1:4*nd, me), grown)
        if (.not. (dyn .or. any(db%prank == q))) cycle
        nto = nto + 1
        to(nto) = q
        do k = 1, nown
          take = any(db%prank(db%pptr(k):db%pptr(k + 1) - 1) == q)
          if (dyn .and. .not. take) take = all(b%x_pred(:, k) >= grown(1:nd)) .and. &
            all(b%x_pred(:, k) <= grown(nd + 1:2*nd))
          if (.not. take) cycle
          if (n == size(sids)) sids = [sids, sids]
          n = n + 1
          sids(n) = k
        end do
        sptr(nto + 1) = n + 1
      end do
      ! what it receives: from each rank whose master box overlaps its grown slave box,
      ! or that owns a partner of its own surface particles (the same tests as the sender's)
      allocate(from(nr))
      nfrom = 0
      grown = [boxes(1:nd, me) - w, boxes(nd + 1:2*nd, me) + w]
      do q = 0, nr - 1
        if (q == me) cycle
        dyn = w >= 0.0_wp .and. overlap(boxes(2*nd + 1:4*nd, q), grown)
        if (.not. dyn) dyn = any(db%pq == q)
        if (.not. dyn) cycle
        nfrom = nfrom + 1
        from(nfrom) = q
      end do
      db%to = to(1:nto)
      db%sptr = sptr(1:nto + 1)
      db%sids = sids(1:n)
      db%from = from(1:nfrom)
      ! each particle sent as (number in the whole body, volume, inverse mass, reference
      ! position, support, position at the step start, now[, neighbour radius])
      rx = allocated(b%rex)
      nw = 3 + 4*nd + merge(1, 0, rx)
      call ensure(db%sbuf, nw*n)
      do k = 1, n
        i = db%sids(k)
        m = nw*(k - 1)
        db%sbuf(m + 1:m + 3) = [real(b%glob(i), wp), b%vol(i), b%imass(i)]
        db%sbuf(m + 4:m + 3 + 4*nd) = [b%x_ref(:, i), b%rho(:, i), b%x_old(:, i), &
          b%x_pred(:, i)]
        if (rx) db%sbuf(m + nw) = b%rex(i)
      end do
      db%mptr(1:nto + 1) = nw*(db%sptr - 1) + 1
      call comm%sparse_exchange(db%to, db%mptr(1:nto + 1), db%sbuf(1:nw*n), db%from, &
        db%nptr(1:nfrom + 1), db%rbuf)
      if (allocated(db%rptr)) deallocate(db%rptr)
      db%rptr = (db%nptr(1:nfrom + 1) - 1)/nw + 1
      ng = db%rptr(nfrom + 1) - 1
      ! the ghosts ascending by their numbers, after the own particles
      allocate(gid(ng), key(ng), ord(ng), src(ng))
      do k = 1, nfrom
        src(db%rptr(k):db%rptr(k + 1) - 1) = db%from(k)
      end do
      do m = 1, ng
        gid(m) = nint(db%rbuf(nw*(m - 1) + 1))
        key(m) = real(gid(m), wp)
      end do
      call sort_index(key, ord)
      call side_take(b, [(k, k = 1, nown)], nown + ng)
      db%held = max(db%held, b%np)
      call take_i1(b%glob, [(k, k = 1, nown)], nown + ng, 0)
      call take_i1(db%owner, [(k, k = 1, nown)], nown + ng, me)
      call take_i1(db%gl, [(k, k = 1, nown)], nown + ng, 0)
      if (allocated(db%rids)) deallocate(db%rids)
      allocate(db%rids(ng))
      do r = 1, ng
        m = ord(r)
        i = nown + r
        db%rids(m) = i
        k = nw*(m - 1)
        b%glob(i) = gid(m)
        b%vol(i) = db%rbuf(k + 2)
        b%imass(i) = db%rbuf(k + 3)
        b%x_ref(:, i) = db%rbuf(k + 4:k + 3 + nd)
        b%rho(:, i) = db%rbuf(k + 4 + nd:k + 3 + 2*nd)
        b%x_old(:, i) = db%rbuf(k + 4 + 2*nd:k + 3 + 3*nd)
        b%x_pred(:, i) = db%rbuf(k + 4 + 3*nd:k + 3 + 4*nd)
        if (rx) b%rex(i) = db%rbuf(k + nw)
        db%owner(i) = src(m)
      end do
      ! the rank's cloud and surface: its own particles and the ghosts, in the order of
      ! their numbers (the serial one)
      call merge_order(b%glob(1:nown), b%glob(nown + 1:nown + ng), db%loc)
      call cloud_init(b%cloud, b%x_ref(:, db%loc), b%rho(:, db%loc), b%vol(db%loc), b%kid, &
        b%wshape, b%bid, b%h, err)
      if (allocated(err)) return
      b%cloud%rmax(1:size(db%rmax)) = db%rmax
      ! self-contact: det(M) without a point's reference neighbours (cloud_det_excluding)
      if (p%self) call cloud_set_reference(b%cloud, b%x_ref(:, db%loc), p%self_radius)
      if (nd == 3) then
        ! the facets whose three vertices the rank holds
        call held_facets()
      else
        allocate(num0(db%full%nseg), num1(db%full%nseg))
        do m = 1, db%full%nseg
          num0(m) = place(db%full%i0(m))
          num1(m) = place(db%full%i1(m))
        end do
        call surface_subset(db%full, num0, num1, b%surface)
      end if
      if (allocated(db%xl)) deallocate(db%xl)
      allocate(db%xl(size(b%x_pred, 1), size(db%loc)))
      if (w < 0.0_wp) return
      db%width = w
      db%nrefresh = db%nrefresh + 1
      db%xr_m = b%x_pred(:, 1:nown)
      db%xr_s = a%x_pred(:, 1:da%nown)
    end associate

  contains

    !> Side ib's surface on this rank: the facets whose three vertices it holds (own or
    !! ghost), in the whole surface's order, with their edge partners among them. They are
    !! its own particles' facets (dist_side_t fid ...) and those the ghosts' owners send
    !! along the ghost plan: each owner the facets of the particles it sends (a facet with
    !! three ghost vertices comes from their owners), once a rank. Collective (the plan's
    !! ranks).
    subroutine held_facets()
      real(wp), allocatable :: fbuf(:), gbuf(:), fkey(:)
      integer, allocatable :: fptr(:), gptr(:), stamp(:), cf(:, :), ord(:), tri(:, :), &
        part(:, :), kept(:), kf(:)
      integer :: pass, k, j, l, f, n, nf, ng, nk, last, v3(3)
      associate (b => p%side(ib), db => p%dist%side(ib), comm => p%dist%comm)
        nf = size(db%fid)
        allocate(stamp(nf), fptr(size(db%to) + 1), fbuf(0))
        ! (the facets of the particles sent to each rank, once a rank: counted, then packed
        ! as their number, vertices and partners)
        do pass = 1, 2
          stamp = 0
          n = 0
          fptr(1) = 1
          do k = 1, size(db%to)
            do j = db%sptr(k), db%sptr(k + 1) - 1
              do l = db%vfptr(db%sids(j)), db%vfptr(db%sids(j) + 1) - 1
                f = db%vfac(l)
                if (stamp(f) == k) cycle
                stamp(f) = k
                n = n + 1
                if (pass == 2) fbuf(7*n - 6:7*n) = real([db%fid(f), db%ftri(:, f), &
                  db%fpart(:, f)], wp)
              end do
            end do
            fptr(k + 1) = 7*n + 1
          end do
          if (pass == 1) then
            deallocate(fbuf)
            allocate(fbuf(7*n))
          end if
        end do
        allocate(gptr(size(db%from) + 1), gbuf(0))
        call comm%sparse_exchange(db%to, fptr, fbuf, db%from, gptr, gbuf)
        ng = (gptr(size(gptr)) - 1)/7
        ! (the rank's own facets and those received, by their numbers in the whole
        ! surface: each kept once, when the rank holds its three vertices)
        allocate(cf(7, nf + ng), fkey(nf + ng), ord(nf + ng))
        do j = 1, nf
          cf(:, j) = [db%fid(j), db%ftri(:, j), db%fpart(:, j)]
        end do
        do j = 1, ng
          cf(:, nf + j) = nint(gbuf(7*j - 6:7*j))
        end do
        fkey = real(cf(1, :), wp)
        call sort_index(fkey, ord)
        allocate(tri(3, nf + ng), kept(nf + ng))
        nk = 0
        last = -1
        do j = 1, nf + ng
          f = ord(j)
          if (cf(1, f) == last) cycle
          last = cf(1, f)
          v3 = [place(cf(2, f)), place(cf(3, f)), place(cf(4, f))]
          if (any(v3 == 0)) cycle
          nk = nk + 1
          tri(:, nk) = v3
          kept(nk) = f
        end do
        ! (an edge's other facet: its place among the kept, 0 when left out)
        allocate(part(3, nk))
        kf = cf(1, kept(1:nk))
        do j = 1, nk
          do l = 1, 3
            part(l, j) = sorted_place(kf, cf(4 + l, kept(j)))
          end do
        end do
        call surface3d_of(tri(:, 1:nk), part, db%cell3, b%x_pred, b%surf3)
      end associate
    end subroutine held_facets

    !> The rank's number of the particle numbered i in the whole body, 0 if not held.
    integer function place(i)
      integer, intent(in) :: i
      associate (b => p%side(ib), nown => p%dist%side(ib)%nown)
        place = sorted_place(b%glob(1:nown), i)
        if (place > 0) return
        place = sorted_place(b%glob(nown + 1:b%np), i)
        if (place > 0) place = nown + place
      end associate
    end function place
  end subroutine make_plan

  !> The places 1..size(x) + size(y) of two ascending lists x and y (y's after x's)
  !! ordered by their values: the merge of the two.
  pure subroutine merge_order(x, y, order)
    integer, intent(in) :: x(:), y(:)
    integer, allocatable, intent(inout) :: order(:)
    integer :: i, j, k, nx
    nx = size(x)
    if (allocated(order)) deallocate(order)
    allocate(order(nx + size(y)))
    i = 1
    j = 1
    do k = 1, size(order)
      if (j > size(y)) then
        order(k) = i
        i = i + 1
      else if (i > nx) then
        order(k) = nx + j
        j = j + 1
      else if (x(i) < y(j)) then
        order(k) = i
        i = i + 1
      else
        order(k) = nx + j
        j = j + 1
      end if
    end do
  end subroutine merge_order

  !> The box [lo(nd), hi(nd)] of the first n particles of x (nd, :) (empty, lo > hi, when
  !! there are none).
  pure function box_of(x, n) result(box)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: n
    real(wp) :: box(2*size(x, 1))
    integer :: k, nd
    nd = size(x, 1)
    box(1:nd) = huge(1.0_wp)
    box(nd + 1:) = -huge(1.0_wp)
    do k = 1, n
      box(1:nd) = min(box(1:nd), x(:, k))
      box(nd + 1:) = max(box(nd + 1:), x(:, k))
    end do
  end function box_of

  !> Do boxes [lo, hi] (lo(nd), hi(nd)) overlap? (An empty box, lo > hi, overlaps none.)
  pure logical function overlap(x, y)
    real(wp), intent(in) :: x(:), y(:)
    integer :: nd
    nd = size(x)/2
    overlap = all(x(1:nd) <= x(nd + 1:)) .and. all(y(1:nd) <= y(nd + 1:)) .and. &
      all(x(1:nd) <= y(nd + 1:)) .and. all(y(1:nd) <= x(nd + 1:))
  end function overlap

  !> a allocated with at least n entries (contents lost when reallocated).
  subroutine ensure(a, n)
    real(wp), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    if (allocated(a)) then
      if (size(a) >= n) return
      deallocate(a)
    end if
    allocate(a(max(n, 1)))
  end subroutine ensure
end submodule contact_dist_sm
