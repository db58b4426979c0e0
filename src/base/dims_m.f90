!> The shapes a solid's geometry gives its data, chosen once at set-up and carried by its
!! tables (solid_tables_t%dims): nodal vectors are (ndim, np), F and P (nf, nq), the
!! symmetric tensors (stresses, back stress, D) (ncomp, nq), the reference gradients of
!! the shape functions (ngrad, nnz). Procedures that are not specialised for one geometry
!! take every extent from here; the kernels that are (tl_kinematics_m, the materials'
!! updates, the table builders) say which layout they serve and are chosen once.
!!
!! Layouts of the plane (plane strain and axisymmetry share them; the hoop terms vanish in
!! plane strain):
!!  F and P: 11, 12, 21, 22, 33 (33 the hoop stretch r/R in axisymmetry);
!!  symmetric tensors: 11, 22, 33, 12 (tensor components);
!!  gradients: dN^1/dX1, dN^1/dX2, dN^2/dX1, dN^2/dX2.
module dims_m
  implicit none
  private
  public :: dims_t, dims_plane, dims_3d, dims_3d_folded, max_dim

  type :: dims_t
    integer :: ndim = 0    !< dimension of space
    integer :: nf = 0      !< stored components of F and P
    integer :: ncomp = 0   !< stored components of a symmetric tensor
    !> reference gradient entries per (point, node): ndim x ndim in the plane (the radial
    !! and axial components' shape functions differ in axisymmetry), ndim in 3D (one shape
    !! function for the three components)
    integer :: ngrad = 0
    integer :: npos = 0    !< position-table entries per (node, node): ndim, or 1 when shared
    integer :: nstab = 0   !< SCNI stabilization stresses per point
    !> the names of a symmetric tensor's stored components, in order (1:ncomp)
    character(len=2) :: tensor_names(6) = ''
    character(len=3) :: axes = ''  !< the coordinates' names in XDMF (GeometryType)
  end type dims_t

  !> Plane strain and axisymmetry (the paper's two geometries).
  type(dims_t), parameter :: dims_plane = dims_t(ndim=2, nf=5, ncomp=4, ngrad=4, npos=2, nstab=4, &
    tensor_names=['11', '22', '33', '12', '  ', '  '], axes='XY')

  !> Three dimensions: F and P 11, 12, 13, 21, ..., 33 (row by row); symmetric tensors 11,
  !! 22, 33, 23, 13, 12 (Voigt's order); gradients dN/dX1, dN/dX2, dN/dX3 of the one shape
  !! function the three components share (no axis to fold: compact tables, a third of the
  !! plane layout's memory per entry), the position table N_I(X_J) once; stabilization
  !! stresses (c, j) for the half cell along X_j, row by row like F.
  type(dims_t), parameter :: dims_3d = dims_t(ndim=3, nf=9, ncomp=6, ngrad=3, npos=1, nstab=9, &
    tensor_names=['11', '22', '33', '23', '13', '12'], axes='XYZ')

  !> Three dimensions with the shape functions folded across symmetry planes (a quarter or
  !! half cylinder, rkpm_tl3d_m): the components' shape functions differ near the planes,
  !! so the gradients are per component, dN^c/dX_j at 3 (c - 1) + j, and the position
  !! table holds N^c for each c; the rest as dims_3d.
  type(dims_t), parameter :: dims_3d_folded = dims_t(ndim=3, nf=9, ncomp=6, ngrad=9, npos=3, &
    nstab=9, tensor_names=['11', '22', '33', '23', '13', '12'], axes='XYZ')

  !> The largest ndim of any geometry: the extent of small fixed-size work arrays, of
  !! which a procedure uses the first ndim entries.
  integer, parameter :: max_dim = 3
end module dims_m
