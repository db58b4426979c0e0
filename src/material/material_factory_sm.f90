!> make_material of material_m: the one place that knows every model. A submodule, because
!! the models extend material_t and so use material_m themselves.
submodule (material_m) material_factory_sm
  use elastic_m, only: elastic_t
  use j2_plastic_m, only: j2_plastic_t
  use viscoplastic_m, only: viscoplastic_t
  implicit none

contains

  !> The model named by params%model after check_material_params (err set, mat left
  !! unallocated, on bad parameters or an unknown name).
  module subroutine make_material(params, mat, err)
    type(material_params_t), intent(in) :: params
    class(material_t), allocatable, intent(out) :: mat
    type(error_t), allocatable, intent(inout) :: err
    call check_material_params(params, err)
    if (allocated(err)) return
    select case (trim(adjustl(lower(params%model))))
    case ('elastic')
      allocate(elastic_t :: mat)
    case ('j2_plastic')
      allocate(j2_plastic_t :: mat)
    case ('viscoplastic')
      allocate(viscoplastic_t :: mat)
    case default
      call set_error(err, "material: variable model = '"//trim(params%model)// &
        "' is not a material model; use one of: "//join_names(material_names))
      return
    end select
    call mat%init(params)
  end subroutine make_material

end submodule material_factory_sm
