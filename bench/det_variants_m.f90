!> Experimental variants of the 2D bilinear tensor-window det(M) kernel, kept in bench/ as
!! evidence for what limits rk_cloud_m's det_2d_bilinear_tensor (issue 2). Each variant
!! computes the same det(M) as the library (cubic spline window, bilinear basis, 4x4
!! Cholesky); they differ only in how the inner loop is written:
!!   copy       - the library kernel verbatim (window_1d called from kernels_m), to show
!!                that the harness measures the library's cost;
!!   inline     - the cubic spline written into the loop (no call, no select case), with the
!!                library's "cycle when outside the support" branch kept;
!!   branchless - no branch at all in the loop: w(a) = ((2-a)_+^3 - 4 (1-a)_+^3)/6, which
!!                is 0 outside the support, so every candidate of a cell row is summed and
!!                the row loop vectorizes;
!!   soa        - branchless, on structure-of-arrays copies with 4 V/(rho_x rho_y) and
!!                2/rho precomputed (built once per body, as bins are).
!! fine_cloud repacks a cloud on bins of cell size rmax/k (whatever cloud_init chose), so any
!! kernel above can be timed with fewer wasted candidates per query.
!! Not part of mfcd_core: the lead decides what moves to src/.
module det_variants_m
  use kinds_m, only: wp
  use kernels_m, only: window_1d
  use rk_cloud_m, only: rk_cloud_t
  use neighbour_bins_m, only: bins_t, bins_build, bins_cell_block
  use errors_m, only: error_t
  use moment_matrix_m, only: singular_pivot
  implicit none
  private
  public :: soa_cloud_t, soa_build, fine_cloud, det_copy, det_inline, det_branchless, det_soa
  public :: det_plain_3d

  !> Structure-of-arrays view of a 2D cloud, in the cloud's bin order.
  type :: soa_cloud_t
    real(wp), allocatable :: x(:), y(:)      !< positions (m)
    real(wp), allocatable :: sx(:), sy(:)    !< 2/rho per direction (1/m)
    real(wp), allocatable :: wv(:)           !< 4 vol/(rho_x rho_y), window prefactor
  end type soa_cloud_t

contains

  !> The plain compiled loop of the 3D detection path (linear basis, cubic spline tensor
  !! window, 4x4 Cholesky; rk_cloud_m's det_3d_linear_tensor): the same arithmetic written
  !! as one loop nest with the cell block, the window and the factorization inline, no call
  !! at all. The yardstick the library path is measured against (issue 23: >= 0.9x of it).
  pure real(wp) function det_plain_3d(c, p) result(det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(3)
    integer :: clo(3), chi(3), d, j, k, cc, q
    real(wp) :: a, z, dx, dy, dz, ax, ay, az, wx, wy, wz, w, z1, z2, z3
    real(wp) :: m11, m12, m13, m14, m22, m23, m24, m33, m34, m44
    real(wp) :: l11, l21, l31, l41, l22, l32, l42, l33, l43, l44, s
    det = 0.0_wp
    do d = 1, 3
      a = (p(d) - c%rmax(d) - c%bins%lo(d))*c%bins%inv_cell(d)
      z = (p(d) + c%rmax(d) - c%bins%lo(d))*c%bins%inv_cell(d)
      if (z < 0.0_wp .or. a >= real(c%bins%ncg(d), wp)) return
      clo(d) = max(0, int(a), c%bins%off(d)) - c%bins%off(d)
      chi(d) = min(c%bins%ncg(d) - 1, int(z), c%bins%off(d) + c%bins%nc(d) - 1) - &
        c%bins%off(d)
      if (clo(d) > chi(d)) return
    end do
    m11 = 0.0_wp; m12 = 0.0_wp; m13 = 0.0_wp; m14 = 0.0_wp; m22 = 0.0_wp
    m23 = 0.0_wp; m24 = 0.0_wp; m33 = 0.0_wp; m34 = 0.0_wp; m44 = 0.0_wp
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        cc = 1 + c%bins%nc(1)*(j + c%bins%nc(2)*k)
        do q = c%bins%start(cc + clo(1)), c%bins%start(cc + chi(1) + 1) - 1
          dx = c%x(1, q) - p(1)
          dy = c%x(2, q) - p(2)
          dz = c%x(3, q) - p(3)
          if (abs(dx) >= c%rho(1, q) .or. abs(dy) >= c%rho(2, q) .or. &
            abs(dz) >= c%rho(3, q)) cycle
          ax = 2.0_wp*abs(dx)*c%rinv(1, q)
          ay = 2.0_wp*abs(dy)*c%rinv(2, q)
          az = 2.0_wp*abs(dz)*c%rinv(3, q)
          if (ax < 1.0_wp) then
            wx = 2.0_wp/3.0_wp - ax*ax*(1.0_wp - 0.5_wp*ax)
          else
            wx = (2.0_wp - ax)**3/6.0_wp
          end if
          if (ay < 1.0_wp) then
            wy = 2.0_wp/3.0_wp - ay*ay*(1.0_wp - 0.5_wp*ay)
          else
            wy = (2.0_wp - ay)**3/6.0_wp
          end if
          if (az < 1.0_wp) then
            wz = 2.0_wp/3.0_wp - az*az*(1.0_wp - 0.5_wp*az)
          else
            wz = (2.0_wp - az)**3/6.0_wp
          end if
          w = 8.0_wp*c%rinv(1, q)*c%rinv(2, q)*c%rinv(3, q)*c%vol(q)*wx*wy*wz
          z1 = dx*c%hinv(1)
          z2 = dy*c%hinv(2)
          z3 = dz*c%hinv(3)
          m11 = m11 + w
          m12 = m12 + w*z1
          m13 = m13 + w*z2
          m14 = m14 + w*z3
          m22 = m22 + w*z1*z1
          m23 = m23 + w*z1*z2
          m24 = m24 + w*z1*z3
          m33 = m33 + w*z2*z2
          m34 = m34 + w*z2*z3
          m44 = m44 + w*z3*z3
        end do
      end do
    end do
    if (m11 <= 0.0_wp) return
    l11 = sqrt(m11)
    l21 = m12/l11
    l31 = m13/l11
    l41 = m14/l11
    s = m22 - l21*l21
    if (s <= singular_pivot*m22) return
    l22 = sqrt(s)
    l32 = (m23 - l31*l21)/l22
    l42 = (m24 - l41*l21)/l22
    s = m33 - l31*l31 - l32*l32
    if (s <= singular_pivot*m33) return
    l33 = sqrt(s)
    l43 = (m34 - l41*l31 - l42*l32)/l33
    s = m44 - l41*l41 - l42*l42 - l43*l43
    if (s <= singular_pivot*m44) return
    l44 = sqrt(s)
    det = (l11*l22*l33*l44)**2
  end function det_plain_3d

  subroutine soa_build(c, s)
    type(rk_cloud_t), intent(in) :: c
    type(soa_cloud_t), intent(out) :: s
    s%x = c%x(1, :)
    s%y = c%x(2, :)
    s%sx = 2.0_wp*c%rinv(1, :)
    s%sy = 2.0_wp*c%rinv(2, :)
    s%wv = 4.0_wp*c%rinv(1, :)*c%rinv(2, :)*c%vol
  end subroutine soa_build

  !> cf: the cloud c repacked on bins with cells rmax/k wide (k >= 1), bin order as in
  !! rk_cloud_m's cloud_init; perm still maps to the caller's particle numbers.
  subroutine fine_cloud(c, k, cf, err)
    type(rk_cloud_t), intent(in) :: c
    integer, intent(in) :: k
    type(rk_cloud_t), intent(out) :: cf
    type(error_t), allocatable, intent(inout) :: err
    type(bins_t) :: b0
    integer :: q, i
    cf = c
    call bins_build(b0, c%x, c%rmax(1:c%ndim)/real(k, wp), err)
    if (allocated(err)) return
    do q = 1, c%np
      i = b0%idx(q)
      cf%perm(q) = c%perm(i)
      cf%x(:, q) = c%x(:, i)
      cf%rho(:, q) = c%rho(:, i)
      cf%rinv(:, q) = c%rinv(:, i)
      cf%vol(q) = c%vol(i)
    end do
    cf%bins = b0
    do q = 1, c%np
      cf%bins%idx(q) = q
    end do
  end subroutine fine_cloud

  !> The library's det_2d_bilinear_tensor, verbatim.
  pure real(wp) function det_copy(c, p) result(det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    integer :: clo(3), chi(3), j, cc, q
    logical :: empty
    real(wp) :: dx, dy, w, z1, z2, z12, h1, h2
    real(wp) :: m11, m12, m13, m14, m22, m24, m33, m34, m44
    det = 0.0_wp
    call bins_cell_block(c%bins, p, c%rmax, clo, chi, empty)
    if (empty) return
    h1 = c%hinv(1)
    h2 = c%hinv(2)
    m11 = 0.0_wp; m12 = 0.0_wp; m13 = 0.0_wp; m14 = 0.0_wp; m22 = 0.0_wp
    m24 = 0.0_wp; m33 = 0.0_wp; m34 = 0.0_wp; m44 = 0.0_wp
    do j = clo(2), chi(2)
      cc = 1 + c%bins%nc(1)*j
      do q = c%bins%start(cc + clo(1)), c%bins%start(cc + chi(1) + 1) - 1
        dx = c%x(1, q) - p(1)
        dy = c%x(2, q) - p(2)
        if (abs(dx) >= c%rho(1, q) .or. abs(dy) >= c%rho(2, q)) cycle
        w = 4.0_wp*c%rinv(1, q)*c%rinv(2, q)*c%vol(q) &
          *window_1d(c%kid, 2.0_wp*dx*c%rinv(1, q))*window_1d(c%kid, 2.0_wp*dy*c%rinv(2, q))
        z1 = dx*h1
        z2 = dy*h2
        z12 = z1*z2
        m11 = m11 + w
        m12 = m12 + w*z1
        m13 = m13 + w*z2
        m14 = m14 + w*z12
        m22 = m22 + w*z1*z1
        m33 = m33 + w*z2*z2
        m24 = m24 + w*z12*z1
        m34 = m34 + w*z12*z2
        m44 = m44 + w*z12*z12
      end do
    end do
    det = chol4(m11, m12, m13, m14, m22, m24, m33, m34, m44)
  end function det_copy

  !> Cubic spline inlined, support branch kept.
  pure real(wp) function det_inline(c, p) result(det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    integer :: clo(3), chi(3), j, cc, q
    logical :: empty
    real(wp) :: dx, dy, w, z1, z2, z12, h1, h2
    real(wp) :: m11, m12, m13, m14, m22, m24, m33, m34, m44
    det = 0.0_wp
    call bins_cell_block(c%bins, p, c%rmax, clo, chi, empty)
    if (empty) return
    h1 = c%hinv(1)
    h2 = c%hinv(2)
    m11 = 0.0_wp; m12 = 0.0_wp; m13 = 0.0_wp; m14 = 0.0_wp; m22 = 0.0_wp
    m24 = 0.0_wp; m33 = 0.0_wp; m34 = 0.0_wp; m44 = 0.0_wp
    do j = clo(2), chi(2)
      cc = 1 + c%bins%nc(1)*j
      do q = c%bins%start(cc + clo(1)), c%bins%start(cc + chi(1) + 1) - 1
        dx = c%x(1, q) - p(1)
        dy = c%x(2, q) - p(2)
        if (abs(dx) >= c%rho(1, q) .or. abs(dy) >= c%rho(2, q)) cycle
        w = 4.0_wp*c%rinv(1, q)*c%rinv(2, q)*c%vol(q) &
          *cubic(2.0_wp*abs(dx)*c%rinv(1, q))*cubic(2.0_wp*abs(dy)*c%rinv(2, q))
        z1 = dx*h1
        z2 = dy*h2
        z12 = z1*z2
        m11 = m11 + w
        m12 = m12 + w*z1
        m13 = m13 + w*z2
        m14 = m14 + w*z12
        m22 = m22 + w*z1*z1
        m33 = m33 + w*z2*z2
        m24 = m24 + w*z12*z1
        m34 = m34 + w*z12*z2
        m44 = m44 + w*z12*z12
      end do
    end do
    det = chol4(m11, m12, m13, m14, m22, m24, m33, m34, m44)
  end function det_inline

  !> No branch in the candidate loop.
  pure real(wp) function det_branchless(c, p) result(det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    integer :: clo(3), chi(3), j, cc, q
    logical :: empty
    real(wp) :: dx, dy, w, z1, z2, z12, h1, h2
    real(wp) :: m11, m12, m13, m14, m22, m24, m33, m34, m44
    det = 0.0_wp
    call bins_cell_block(c%bins, p, c%rmax, clo, chi, empty)
    if (empty) return
    h1 = c%hinv(1)
    h2 = c%hinv(2)
    m11 = 0.0_wp; m12 = 0.0_wp; m13 = 0.0_wp; m14 = 0.0_wp; m22 = 0.0_wp
    m24 = 0.0_wp; m33 = 0.0_wp; m34 = 0.0_wp; m44 = 0.0_wp
    do j = clo(2), chi(2)
      cc = 1 + c%bins%nc(1)*j
      do q = c%bins%start(cc + clo(1)), c%bins%start(cc + chi(1) + 1) - 1
        dx = c%x(1, q) - p(1)
        dy = c%x(2, q) - p(2)
        w = 4.0_wp*c%rinv(1, q)*c%rinv(2, q)*c%vol(q) &
          *cubic_bl(2.0_wp*abs(dx)*c%rinv(1, q))*cubic_bl(2.0_wp*abs(dy)*c%rinv(2, q))
        z1 = dx*h1
        z2 = dy*h2
        z12 = z1*z2
        m11 = m11 + w
        m12 = m12 + w*z1
        m13 = m13 + w*z2
        m14 = m14 + w*z12
        m22 = m22 + w*z1*z1
        m33 = m33 + w*z2*z2
        m24 = m24 + w*z12*z1
        m34 = m34 + w*z12*z2
        m44 = m44 + w*z12*z12
      end do
    end do
    det = chol4(m11, m12, m13, m14, m22, m24, m33, m34, m44)
  end function det_branchless

  !> Branchless on structure-of-arrays data.
  pure real(wp) function det_soa(c, s, p) result(det)
    type(rk_cloud_t), intent(in) :: c
    type(soa_cloud_t), intent(in) :: s
    real(wp), intent(in) :: p(:)
    integer :: clo(3), chi(3), j, cc, q
    logical :: empty
    real(wp) :: dx, dy, w, z1, z2, z12, h1, h2, px, py
    real(wp) :: m11, m12, m13, m14, m22, m24, m33, m34, m44
    det = 0.0_wp
    call bins_cell_block(c%bins, p, c%rmax, clo, chi, empty)
    if (empty) return
    h1 = c%hinv(1)
    h2 = c%hinv(2)
    px = p(1)
    py = p(2)
    m11 = 0.0_wp; m12 = 0.0_wp; m13 = 0.0_wp; m14 = 0.0_wp; m22 = 0.0_wp
    m24 = 0.0_wp; m33 = 0.0_wp; m34 = 0.0_wp; m44 = 0.0_wp
    do j = clo(2), chi(2)
      cc = 1 + c%bins%nc(1)*j
      do q = c%bins%start(cc + clo(1)), c%bins%start(cc + chi(1) + 1) - 1
        dx = s%x(q) - px
        dy = s%y(q) - py
        w = s%wv(q)*cubic_bl(abs(dx)*s%sx(q))*cubic_bl(abs(dy)*s%sy(q))
        z1 = dx*h1
        z2 = dy*h2
        z12 = z1*z2
        m11 = m11 + w
        m12 = m12 + w*z1
        m13 = m13 + w*z2
        m14 = m14 + w*z12
        m22 = m22 + w*z1*z1
        m33 = m33 + w*z2*z2
        m24 = m24 + w*z12*z1
        m34 = m34 + w*z12*z2
        m44 = m44 + w*z12*z12
      end do
    end do
    det = chol4(m11, m12, m13, m14, m22, m24, m33, m34, m44)
  end function det_soa

  !> Cubic spline w(a), a = |s| in [0, 2) (the caller has checked the support).
  pure real(wp) function cubic(a) result(w)
    real(wp), intent(in) :: a
    if (a < 1.0_wp) then
      w = 2.0_wp/3.0_wp - a*a*(1.0_wp - 0.5_wp*a)
    else
      w = (2.0_wp - a)**3/6.0_wp
    end if
  end function cubic

  !> Cubic spline for any a >= 0 without a branch: ((2-a)_+^3 - 4 (1-a)_+^3)/6.
  pure real(wp) function cubic_bl(a) result(w)
    real(wp), intent(in) :: a
    real(wp) :: t1, t2
    t2 = max(0.0_wp, 2.0_wp - a)
    t1 = max(0.0_wp, 1.0_wp - a)
    w = (t2*t2*t2 - 4.0_wp*t1*t1*t1)*(1.0_wp/6.0_wp)
  end function cubic_bl

  !> det of the bilinear moment matrix (M23 = M14, eq. 19) by the library's 4x4 Cholesky,
  !! with its relative singular-pivot test.
  pure real(wp) function chol4(m11, m12, m13, m14, m22, m24, m33, m34, m44) result(det)
    real(wp), intent(in) :: m11, m12, m13, m14, m22, m24, m33, m34, m44
    real(wp) :: l11, l21, l31, l41, l22, l32, l42, l33, l43, l44, s
    det = 0.0_wp
    if (m11 <= 0.0_wp) return
    l11 = sqrt(m11)
    l21 = m12/l11
    l31 = m13/l11
    l41 = m14/l11
    s = m22 - l21*l21
    if (s <= singular_pivot*m22) return
    l22 = sqrt(s)
    l32 = (m14 - l31*l21)/l22
    l42 = (m24 - l41*l21)/l22
    s = m33 - l31*l31 - l32*l32
    if (s <= singular_pivot*m33) return
    l33 = sqrt(s)
    l43 = (m34 - l41*l31 - l42*l32)/l33
    s = m44 - l41*l41 - l42*l42 - l43*l43
    if (s <= singular_pivot*m44) return
    l44 = sqrt(s)
    det = (l11*l22*l33*l44)**2
  end function chol4
end module det_variants_m
