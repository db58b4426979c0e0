!> Working precision and index kinds used everywhere in mfcd.
module kinds_m
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  implicit none
  private
  public :: wp, ik, i64, tiny_wp, eps_wp, pi

  integer, parameter :: wp = real64   !< working real kind
  integer, parameter :: ik = int32    !< default index kind
  integer, parameter :: i64 = int64   !< counters that can exceed 2**31
  real(wp), parameter :: tiny_wp = tiny(1.0_wp)
  real(wp), parameter :: eps_wp = epsilon(1.0_wp)
  real(wp), parameter :: pi = 3.141592653589793238462643383279502884_wp
end module kinds_m
