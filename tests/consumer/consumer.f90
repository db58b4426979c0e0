!> Uses an installed mfcd: builds a lattice body on the unit square (generators_m), packs it
!! into an RK cloud (rk_cloud_m) and evaluates det(M) inside the body, where it must be
!! positive, and outside it, where it must be zero (the detection criterion of Section 2).
!! Exits with 1 when either is wrong or mfcd reports an error.
program mfcd_consumer
  use kinds_m, only: wp
  use errors_m, only: error_t
  use body_m, only: body_t
  use generators_m, only: make_rectangle, set_supports
  use kernels_m, only: kernel_cubic, window_tensor
  use basis_m, only: basis_bilinear
  use rk_cloud_m, only: rk_cloud_t, cloud_init, cloud_det
  use version_m, only: code_name, code_version
  implicit none
  type(body_t) :: b
  type(rk_cloud_t) :: c
  type(error_t), allocatable :: err
  real(wp) :: det_in, det_out

  ! 11 x 11 particles on [0, 1]^2 (spacing 0.1), supports twice the spacing
  call make_rectangle(b, [0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp], [11, 11], err)
  if (allocated(err)) call fail(err%message)
  call set_supports(b, [2.0_wp, 2.0_wp])
  call cloud_init(c, b%x, b%rho, b%vol, kernel_cubic, window_tensor, basis_bilinear, &
    b%h(1:2), err)
  if (allocated(err)) call fail(err%message)

  det_in = cloud_det(c, [0.43_wp, 0.57_wp])
  det_out = cloud_det(c, [1.5_wp, 0.5_wp])
  print '(a, 1x, a, ": ", i0, " particles")', code_name, code_version, b%np
  print '("det M(0.43, 0.57) = ", es12.5, "  (inside: must be > 0)")', det_in
  print '("det M(1.50, 0.50) = ", es12.5, "  (outside: must be 0)")', det_out
  if (.not. (det_in > 0.0_wp)) call fail('det(M) inside the body is not positive')
  if (det_out /= 0.0_wp) call fail('det(M) outside the body is not zero')
  print '(a)', 'mfcd_consumer: ok'

contains

  subroutine fail(msg)
    character(len=*), intent(in) :: msg
    print '("mfcd_consumer: error: ", a)', msg
    error stop 1
  end subroutine fail
end program mfcd_consumer
