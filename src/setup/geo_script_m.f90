!> The gmsh script subset mfcd reads (&body shape = 'geo'): mfcd's own reader of the part of
!! gmsh's .geo language that builds a model (variables, arithmetic, If blocks, points,
!! curves, loops, surfaces, volumes, physical groups, mesh-size fields and Mesh options),
!! which turns a script and the deck's numbers into a list of gmsh API calls with plain
!! numbers (geo_model_t). gmsh_mesh_m makes those calls; gmsh's own interpreter never sees
!! the user's text. Anything outside the subset is refused with the line it is on, before
!! anything runs: a list of refused words could never be complete for gmsh's language,
!! whose command names can be built from strings at run time and whose options and
!! plugins act without commands, so the subset is an allowlist (doc/deck.md, "The gmsh
!! script subset").
!!
!! The reader follows gmsh's grammar (src/parser/Gmsh.y of gmsh 4) where the two overlap:
!! its operators and their precedence, its functions, its newp/newl/... numbering, and an
!! assignment that overwrites a number the caller set (gmsh::parser::setNumber). It is
!! stricter where gmsh is lax: tags must be whole numbers, every entity a statement names
!! must exist, every number must be finite, and a branch of an If that is not taken is
!! still read (gmsh skips it unread). Its work is linear in the length of the script:
!! names and tags are hashed (hash_map_m), there are no loops, macros or includes, and
!! expressions nest at most max_depth deep.
!!
!! geo_min_triangles bounds the size of the mesh before gmsh runs: from the surfaces' areas
!! and an upper bound of the mesh size at each point, a count of triangles the mesh cannot
!! go much below.
module geo_script_m
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use, intrinsic :: ieee_exceptions, only: ieee_status_type, ieee_get_status, &
    ieee_set_status, ieee_set_halting_mode, ieee_all
  use kinds_m, only: wp
  use hash_map_m, only: name_map_t, tag_map_t
  use strings_m, only: itoa, rtoa, edit_distance
  use geometry_m, only: cross => cross3
  implicit none
  private
  public :: geo_model_t, geo_parse, geo_min_triangles, geo_field_type, geo_field_option, &
    geo_mesh_option, geo_subset_text

  !> Largest script read (bytes): far above any geometry script (the shipped ones are 2 kB).
  integer, parameter, public :: geo_max_bytes = 1048576

  !> The kinds of API call (geo_model_t%kind).
  integer, parameter, public :: op_point = 1, op_line = 2, op_circle = 3, op_ellipse = 4, &
    op_spline = 5, op_bspline = 6, op_curve_loop = 7, op_plane_surface = 8, op_surface = 9, &
    op_surface_loop = 10, op_volume = 11, op_field = 12, op_field_number = 13, &
    op_field_list = 14, op_background = 15, op_mesh_option = 16

  !> Deepest nesting of parentheses, operators and If blocks (the reader recurses).
  integer, parameter :: max_depth = 200
  !> Most values one list may hold, ranges such as {1:10} expanded.
  integer, parameter :: max_list = 100000
  !> Most values all lists together may hold.
  integer, parameter :: max_values = 2000000
  !> Longest word of a table entry.
  integer, parameter :: word_len = 72
  !> Longest name and string.
  integer, parameter :: max_name = 64, max_string = 256
  !> gmsh's tags are C ints.
  integer, parameter :: max_tag = huge(1)

  !> The model a script builds: its API calls in the script's order, as structure of arrays.
  !! Call k is kind(k) on tag(k), from script line line(k); its integer arguments are
  !! ints(i0(k) : i0(k) + ni(k) - 1), its real ones reals(r0(k) : r0(k) + nr(k) - 1), and
  !! sub(k) is the field type (op_field: geo_field_type), the field option (op_field_number,
  !! op_field_list: geo_field_option) or the Mesh option (op_mesh_option: geo_mesh_option).
  !! op_point: reals x, y, z, mesh size (0: none). op_line: ints start, end. op_circle:
  !! start, centre, end. op_ellipse: start, centre, major-axis point, end. op_spline,
  !! op_bspline: points. op_curve_loop: signed curves. op_plane_surface, op_surface: curve
  !! loops. op_surface_loop: surfaces. op_volume: surface loops. op_field: tag only.
  !! op_field_number: reals(1); op_field_list: the reals. op_background: the field's tag.
  !! op_mesh_option: reals(1).
  type :: geo_model_t
    integer :: nops = 0
    integer, allocatable :: kind(:), tag(:), line(:), sub(:), i0(:), ni(:), r0(:), nr(:)
    integer :: nints = 0, nreals = 0
    integer, allocatable :: ints(:)
    real(wp), allocatable :: reals(:)
    !> Plane surfaces and (filling) surfaces: what generate(2) meshes.
    integer :: nsurfaces = 0
  end type geo_model_t

  ! --- tokens
  integer, parameter :: tk_num = 1, tk_name = 2, tk_str = 3, tk_op = 4, tk_end = 5

  ! --- entity classes (parser_t%ent) and their names in messages
  integer, parameter :: ent_point = 1, ent_curve = 2, ent_loop = 3, ent_surface = 4, &
    ent_shell = 5, ent_volume = 6, ent_field = 7, ent_physical = 8
  character(len=*), parameter :: ent_names(8) = [character(len=14) :: 'Point', 'curve', &
    'Curve Loop', 'surface', 'Surface Loop', 'Volume', 'Field', 'physical group']

  !> Field types of the subset.
  character(len=*), parameter :: field_types(9) = [character(len=9) :: 'Distance', &
    'Threshold', 'Min', 'Max', 'Box', 'Ball', 'Cylinder', 'Constant', 'Restrict']

  !> Field options of the subset, 'Type Option kind[=Canonical]': the kind says what the
  !! value must be: N a finite number, D a finite number >= 0, P a finite number > 0, B 0 or
  !! 1, I a whole number in 1 .. 100000, F a field's tag, LF a list of fields' tags, L0 .. L3
  !! a list of tags of points, curves, surfaces or volumes. IField, LcMin and LcMax are
  !! gmsh's older names of InField, SizeMin and SizeMax.
  character(len=*), parameter :: field_options(48) = [character(len=40) :: &
    'Distance PointsList L0', 'Distance CurvesList L1', 'Distance SurfacesList L2', &
    'Distance Sampling I', &
    'Threshold InField F', 'Threshold SizeMin P', 'Threshold SizeMax P', &
    'Threshold DistMin D', 'Threshold DistMax D', 'Threshold Sigmoid B', &
    'Threshold StopAtDistMax B', 'Threshold IField F=InField', &
    'Threshold LcMin P=SizeMin', 'Threshold LcMax P=SizeMax', &
    'Min FieldsList LF', 'Max FieldsList LF', &
    'Box VIn P', 'Box VOut P', 'Box XMin N', 'Box XMax N', 'Box YMin N', 'Box YMax N', &
    'Box ZMin N', 'Box ZMax N', 'Box Thickness D', &
    'Ball VIn P', 'Ball VOut P', 'Ball Radius D', 'Ball XCenter N', 'Ball YCenter N', &
    'Ball ZCenter N', 'Ball Thickness D', &
    'Cylinder VIn P', 'Cylinder VOut P', 'Cylinder Radius D', 'Cylinder XCenter N', &
    'Cylinder YCenter N', 'Cylinder ZCenter N', 'Cylinder XAxis N', 'Cylinder YAxis N', &
    'Cylinder ZAxis N', &
    'Constant VIn P', 'Constant VOut P', 'Constant SurfacesList L2', &
    'Restrict InField F', 'Restrict CurvesList L1', 'Restrict SurfacesList L2', &
    'Restrict VolumesList L3']

  !> Mesh options of the subset, 'Name kind[=Canonical]': D, P, B as for fields; C a whole
  !! number in 0 .. 10000; X one of -3, -2, 0, 1, 2 (gmsh's choices of extending sizes into
  !! surfaces); A2, A3 gmsh's 2D and 3D algorithm numbers; S a whole number in 0 .. 100; U a
  !! number in 0 .. 1; R a whole number in 0 .. 2^31 - 1; O the element order, 1 only (mfcd
  !! takes linear triangles). The older CharacteristicLength* names are gmsh's aliases.
  character(len=*), parameter :: mesh_options(24) = [character(len=72) :: &
    'MeshSizeMin D', 'MeshSizeMax P', 'MeshSizeFactor P', 'MeshSizeFromPoints B', &
    'MeshSizeFromCurvature C', 'MeshSizeExtendFromBoundary X', 'Algorithm A2', &
    'Algorithm3D A3', 'Smoothing S', 'Optimize B', 'OptimizeNetgen B', &
    'OptimizeThreshold U', 'RandomFactor P', 'RandomSeed R', 'ElementOrder O', &
    'MinimumCirclePoints C', 'MinimumCurvePoints C', &
    'MinimumElementsPerTwoPi C=MeshSizeFromCurvature', &
    'CharacteristicLengthMin D=MeshSizeMin', 'CharacteristicLengthMax P=MeshSizeMax', &
    'CharacteristicLengthFactor P=MeshSizeFactor', &
    'CharacteristicLengthFromPoints B=MeshSizeFromPoints', &
    'CharacteristicLengthFromCurvature C=MeshSizeFromCurvature', &
    'CharacteristicLengthExtendFromBoundary X=MeshSizeExtendFromBoundary']

  !> The one-argument and two-argument functions of the subset (gmsh's, with its aliases).
  character(len=*), parameter :: functions1 = ' Exp Log Log10 Sqrt Sin Asin ArcSin Cos '// &
    'Acos ArcCos Tan Atan ArcTan Sinh Cosh Tanh Fabs Abs Floor Ceil Round Step '
  character(len=*), parameter :: functions2 = ' Atan2 ArcTan2 Fmod Modulo Hypot Max Min '

  !> The words of gmsh's language (its lexer's keywords, gmsh 4), so that a message can name
  !! one that the subset does not read.
  character(len=*), parameter :: gmsh_words = ' newreg newp newl newc newll newcl news '// &
    'newsl newv newf Abort Abs AbsolutePath Acos AdaptMesh Affine Alias AliasWithOptions '// &
    'ArcCos Append ArcSin ArcTan ArcTan2 Asin Atan Atan2 BSpline Betti Bezier Box Block '// &
    'BooleanCoherence BooleanCommon BooleanCut BooleanDifference BooleanFragments '// &
    'BooleanFuse BooleanIntersection BooleanSection BooleanUnion BoundingBox Call Catenary '// &
    'CatmullRom Ceil CenterOfMass Chamfer Characteristic Circle ClassifySurfaces Closest '// &
    'CodeName Coherence Cohomology Color ColorTable Combine Compound Cone Coordinates '// &
    'CopyOptions Cos Cosh Cpu CreateGeometry CreateTopology CreateMeshEdges '// &
    'CreateMeshFaces CurrentDir CurrentDirectory CurrentFileName Curvature Curve Cylinder '// &
    'DefineConstant DefineNumber DefineString Degenerated Delete Dilate DimNameSpace '// &
    'DirName Disk Draw Ellipse Ellipsis Ellipsoid Elliptic Else ElseIf EndFor EndIf Error '// &
    'Euclidian Euclidean Exists Exit Exp Extrude Fabs Field FileExists Fillet Find '// &
    'FixRelativePath Floor Fmod For Function GMSH_MAJOR_VERSION GMSH_MINOR_VERSION '// &
    'GMSH_PATCH_VERSION GeoEntity GetEnv GetForced GetForcedStr GetNumber GetString '// &
    'GetStringValue GetValue GmshExecutableName HealShapes Hide Hole Homology Hypot '// &
    'INTERPOLATION_SCHEME If In Intersect Knots Layers Length Levelset LinSpace Line List '// &
    'ListFromFile Log Log10 LogSpace LowerCase LowerCaseIn MPI_Rank MPI_Size Macro Mass '// &
    'MatrixOfInertia Max Memory MeshAlgorithm MeshSize MeshSizeFromBoundary Min Modulo '// &
    'N2S NameStruct NameToString NewModel Normal Nurbs OnelabAction OnelabRun Order '// &
    'Parametric Parent Periodic Physical Pi Plane Plugin Point PolarSphere Printf Quadric '// &
    'Rand Recursive Recombine Rectangle RecombineMesh RefineMesh RelocateMesh ReorientMesh '// &
    'RenumberMeshNodes RenumberMeshElements Return ReverseMesh Reverse Rotate Round Ruled '// &
    'S2N ScaleLastLayer SetChanged SetFactory SetTag SetMaxTag SetNumber SetPartition '// &
    'SetString Sewing ShapeFromFile Show Sin Sinh Slide Smoother Sphere Spline Split '// &
    'Sprintf Sqrt Step Str StrCat StrChoice StrCmp StrFind StrLen StrPrefix StrRelative '// &
    'StrReplace StrSub StringToName Struct Surface Symmetry SyncModel T2 T3 TIME Tan Tanh '// &
    'TestLevel TextAttributes ThickSolid ThruSections Today Torus TotalMemory '// &
    'TransformMesh Transfinite Translate UndefineConstant Unique UnsplitWindow UpperCase '// &
    'Using Volume Warning Wedge Wire SystemCall NonBlockingSystemCall System Include '// &
    'Merge MergeWithBoundingBox Save Print Sleep CreateDir DeleteFile RenameFile '// &
    'SendToServer Background Loop '

  !> Option categories of gmsh other than Mesh (a script may set none of them).
  character(len=*), parameter :: option_categories = ' General Geometry Print View '// &
    'PostProcessing Solver '

  !> What the subset holds, for messages.
  character(len=*), parameter :: subset_words = "variables, arithmetic, If blocks, "// &
    "Point, Line, Circle, Ellipse, Spline, BSpline, Curve Loop, Plane Surface, Surface, "// &
    "Surface Loop, Volume, Physical groups, Field[n], Background Field and Mesh.* options "// &
    "(doc/deck.md, 'The gmsh script subset')"

  !> The reader's state: the tokens, the variables, the entities defined so far and the
  !! model being built; msg is the first problem found ('' while there is none).
  type :: parser_t
    character(len=:), allocatable :: text
    integer :: nt = 0, k = 1
    integer, allocatable :: tk(:), ta(:), tb(:), tl(:)
    real(wp), allocatable :: tv(:)
    type(name_map_t) :: vars, words
    integer :: nvar = 0
    real(wp), allocatable :: vval(:)
    !> def: has a value; deck: set by the deck; read: read on the path taken; used: named
    !! anywhere (a branch not taken included)
    logical, allocatable :: vdef(:), vdeck(:), vread(:), vused(:)
    type(tag_map_t) :: ent(8)
    integer :: maxtag(8) = 0
    !> each field's type (geo_field_type), by the field's order of definition
    type(tag_map_t) :: field_kind
    integer :: background = 0, background_line = 0
    character(len=:), allocatable :: tested   !< names tested with Exists, comma-separated
    type(geo_model_t) :: m
    character(len=:), allocatable :: msg
    integer :: depth = 0
  end type parser_t

  !> What geo_min_triangles needs of a field: its type, the numbers it was given (par,
  !! with set saying which: 1 SizeMin or VIn, 2 SizeMax or VOut, 3 DistMin or Radius, 4
  !! DistMax or Thickness, 5 InField, 6 Sigmoid, 7 StopAtDistMax, 8-10 XMin, YMin, ZMin or
  !! the centre, 11-13 XMax, YMax, ZMax, 14 Sampling), the fields it reads (Min, Max) and
  !! the sample points of a Distance field (x(:, 1:ns)).
  type :: est_field_t
    integer :: kind = 0
    real(wp) :: par(14) = 0.0_wp
    logical :: set(14) = .false.
    integer, allocatable :: children(:)
    real(wp), allocatable :: x(:, :)
    integer :: ns = 0
  end type est_field_t

  !> The model as geo_min_triangles reads it: calls by tag, the fields, the Mesh options.
  type :: est_t
    type(tag_map_t) :: points, curves, loops, fields
    type(est_field_t), allocatable :: est(:)
    integer :: background = 0
    real(wp) :: size_min = 0.0_wp, size_max = 1.0e22_wp, factor = 1.0_wp
    real(wp) :: from_points = 1.0_wp, extend = 1.0_wp
  end type est_t

contains

  !> The subset, in words (for messages of other modules).
  function geo_subset_text() result(t)
    character(len=:), allocatable :: t
    t = subset_words
  end function geo_subset_text

  !> gmsh's name of field type k.
  function geo_field_type(k) result(name)
    integer, intent(in) :: k
    character(len=:), allocatable :: name
    name = trim(field_types(k))
  end function geo_field_type

  !> gmsh's name (the canonical one) of field option k.
  function geo_field_option(k) result(name)
    integer, intent(in) :: k
    character(len=:), allocatable :: name
    character(len=word_len) :: w(3)
    call entry_words(field_options(k), w)
    name = canonical(w(2), w(3))
  end function geo_field_option

  !> gmsh's name (the canonical one) of Mesh option k, without 'Mesh.'.
  function geo_mesh_option(k) result(name)
    integer, intent(in) :: k
    character(len=:), allocatable :: name
    character(len=word_len) :: w(3)
    call entry_words(mesh_options(k), w)
    name = canonical(w(1), w(2))
  end function geo_mesh_option

  !> Read the script text with the deck's numbers names(k) = values(k) and build its model.
  !! msg is '' when the script is in the subset and consistent; otherwise it says what is
  !! wrong (with the line), and where is 'file' (the script) or 'geo_names' (a deck number
  !! the script never reads, or overwrites before reading it).
  subroutine geo_parse(text, names, values, model, msg, where, which)
    character(len=*), intent(in) :: text, names(:)
    real(wp), intent(in) :: values(:)
    type(geo_model_t), intent(out) :: model
    character(len=:), allocatable, intent(out) :: msg, where
    !> the deck name at fault when where is 'geo_names'
    character(len=:), allocatable, intent(out) :: which
    type(parser_t) :: p
    integer :: k, v
    logical :: found
    type(ieee_status_type) :: fp
    ! the script's arithmetic may overflow or divide by zero: the values are checked for
    ! being finite, so no trap (a Debug build's) may stop the program first
    call ieee_get_status(fp)
    call ieee_set_halting_mode(ieee_all, .false.)
    where = 'file'
    which = ''
    p%text = text
    p%msg = ''
    p%tested = ''
    call load_words(p)
    call tokenize(p)
    if (len(p%msg) == 0) then
      do k = 1, size(names)
        if (is_gmsh_word(p, trim(names(k)))) then
          where = 'geo_names'
          which = trim(names(k))
          p%msg = "'"//trim(names(k))//"' is a word of gmsh's language, not a number a "// &
            "script can read: give the name the script tests with If (!Exists(name))"
          exit
        end if
        v = new_variable(p, trim(names(k)))
        p%vval(v) = values(k)
        p%vdef(v) = .true.
        p%vdeck(v) = .true.
      end do
      p%k = 1
      do while (len(p%msg) == 0 .and. p%tk(p%k) /= tk_end)
        call statement(p, .true.)
      end do
    end if
    if (len(p%msg) == 0) call check_references(p)
    if (len(p%msg) == 0) then
      do k = 1, size(names)
        v = p%vars%get(trim(names(k)), found)
        if (.not. p%vused(v)) then
          where = 'geo_names'
          which = trim(names(k))
          p%msg = "never uses a number '"//trim(names(k))//"'"// &
            nearest_name(p, trim(names(k)))//"; the numbers it lets a caller set (If (!Exists"// &
            "(name))): "//tested_list(p)
          exit
        end if
      end do
    end if
    if (len(p%msg) > 0 .and. index(p%msg, '@geo_names ') == 1) then
      ! '@geo_names name line L: ...' from assignment
      where = 'geo_names'
      p%msg = p%msg(len('@geo_names ') + 1:)
      which = p%msg(1:index(p%msg, ' ') - 1)
      p%msg = p%msg(index(p%msg, ' ') + 1:)
    end if
    msg = p%msg
    if (len(msg) == 0 .and. p%m%nsurfaces == 0) msg = 'the script defines no Plane Surface '// &
      'or Surface, so there is nothing to mesh: give the body its surface (Curve Loop(1) '// &
      '= {...}; Plane Surface(1) = {1};)'
    call finish_model(p%m)
    call move_alloc_model(p%m, model)
    call ieee_set_status(fp)
  end subroutine geo_parse

  ! ------------------------------------------------------------------ words and tables

  subroutine load_words(p)
    type(parser_t), intent(inout) :: p
    integer :: a, z
    a = 1
    do while (a <= len(gmsh_words))
      z = index(gmsh_words(a:), ' ')
      if (z > 1) call p%words%put(gmsh_words(a:a + z - 2), 1)
      a = a + max(z, 1)
    end do
  end subroutine load_words

  logical function is_gmsh_word(p, w)
    type(parser_t), intent(in) :: p
    character(len=*), intent(in) :: w
    integer :: v
    v = p%words%get(w, is_gmsh_word)
  end function is_gmsh_word

  !> The blank-separated words of a table entry: 'Type Option kind=Canonical' gives Type,
  !! Option, kind=Canonical.
  subroutine entry_words(e, w)
    character(len=*), intent(in) :: e
    character(len=word_len), intent(out) :: w(3)
    integer :: a, z, n
    n = 0
    w = ''
    a = 1
    do while (a <= len_trim(e) .and. n < 3)
      z = index(e(a:)//' ', ' ')
      if (z > 1) then
        n = n + 1
        w(n) = e(a:a + z - 2)
      end if
      a = a + z
    end do
  end subroutine entry_words

  !> name, or the canonical name after '=' in kind.
  function canonical(name, kind) result(c)
    character(len=*), intent(in) :: name, kind
    character(len=:), allocatable :: c
    integer :: e
    e = index(kind, '=')
    if (e > 0) then
      c = trim(kind(e + 1:))
    else
      c = trim(name)
    end if
  end function canonical

  !> The kind of a table entry without its canonical name: 'P=SizeMin' gives 'P'.
  function kind_of(kind) result(c)
    character(len=*), intent(in) :: kind
    character(len=:), allocatable :: c
    integer :: e
    e = index(kind, '=')
    if (e > 0) then
      c = kind(1:e - 1)
    else
      c = trim(kind)
    end if
  end function kind_of

  ! ------------------------------------------------------------------ tokens

  !> The script's tokens, with their lines. Only plain text is read: bytes above 127 in
  !! comments and strings only, no control character but tab, line feed, carriage return
  !! and form feed.
  subroutine tokenize(p)
    type(parser_t), intent(inout) :: p
    integer :: i, j, n, line, c, l0, ios
    character :: ch, nx
    real(wp) :: v
    n = len(p%text)
    allocate(p%tk(64), p%ta(64), p%tb(64), p%tl(64), p%tv(64))
    line = 1
    i = 1
    do while (i <= n)
      ch = p%text(i:i)
      c = ichar(ch)
      nx = ' '
      if (i < n) nx = p%text(i + 1:i + 1)
      if (ch == achar(10) .or. (c == 13 .and. nx /= achar(10))) then
        ! a line ends with LF, CR LF or CR alone (as gmsh's reader takes them)
        line = line + 1
        i = i + 1
      else if (ch == ' ' .or. c == 9 .or. c == 13 .or. c == 12) then
        i = i + 1
      else if (i == 1 .and. p%text(1:min(3, n)) == char(239)//char(187)//char(191)) then
        ! a UTF-8 byte order mark, as some editors write one
        i = 4
      else if (ch == '/' .and. nx == '/') then
        j = scan(p%text(i:), achar(10)//achar(13))
        if (j == 0) j = n - i + 2
        if (.not. plain(p%text(i:i + j - 2), .true.)) return
        i = i + j - 1
      else if (ch == '/' .and. nx == '*') then
        l0 = line
        j = index(p%text(i + 2:), '*/')
        if (j == 0) then
          call fail_at(p, l0, 'a comment opened with /* is never closed with */')
          return
        end if
        if (.not. plain(p%text(i:i + j + 2), .true.)) return
        line = line + count_lf(p%text(i:i + j + 2))
        i = i + j + 3
      else if (ch == '"') then
        j = index(p%text(i + 1:), '"')
        if (j == 0) then
          call fail_at(p, line, 'a string opened with " is never closed')
          return
        end if
        if (scan(p%text(i + 1:i + j - 1), achar(10)//achar(13)) > 0 .or. &
          index(p%text(i + 1:i + j - 1), '\') > 0 .or. j - 1 > max_string) then
          call fail_at(p, line, 'a string holds a line break or a backslash, or is longer '// &
            'than '//itoa(max_string)//' characters: give a short one-line name')
          return
        end if
        if (.not. plain(p%text(i + 1:i + j - 1), .true.)) return
        call add_token(p, tk_str, i + 1, i + j - 1, line, 0.0_wp)
        i = i + j + 1
      else if (is_digit(ch) .or. (ch == '.' .and. is_digit(nx))) then
        ! gmsh's numbers: 12, 1.5, .5, 1., 1e-3, 1.5E+3
        j = number_end(p%text, i)
        read(p%text(i:j - 1), *, iostat=ios) v
        if (ios /= 0 .or. .not. ieee_is_finite(v) .or. j - i > 400) then
          call fail_at(p, line, 'the number '//p%text(i:min(j - 1, i + 39))//' is out of '// &
            'range (give a finite number of at most 400 characters)')
          return
        end if
        call add_token(p, tk_num, i, j - 1, line, v)
        i = j
      else if (is_alpha(ch)) then
        j = i
        do while (j <= n)
          if (.not. (is_alpha(p%text(j:j)) .or. is_digit(p%text(j:j)))) exit
          j = j + 1
        end do
        if (j - i > max_name) then
          call fail_at(p, line, 'a name is longer than '//itoa(max_name)//' characters')
          return
        end if
        call add_token(p, tk_name, i, j - 1, line, 0.0_wp)
        i = j
      else if (is_two(ch//nx)) then
        call add_token(p, tk_op, i, i + 1, line, 0.0_wp)
        i = i + 2
      else if (index('()[]{},;=.:?+-*/%^!<>', ch) > 0) then
        call add_token(p, tk_op, i, i, line, 0.0_wp)
        i = i + 1
      else if (c >= 32 .and. c < 127) then
        call fail_at(p, line, "the character "//ch//" is not part of the gmsh script "// &
          "subset mfcd reads (it has no strings in single quotes, no # or $, no bit "// &
          "operators); the subset: "//subset_words)
        return
      else
        call fail_at(p, line, 'byte '//itoa(c)//' is not plain text: a .geo script is '// &
          'ASCII text (UTF-8 only in comments and strings)')
        return
      end if
    end do
    call add_token(p, tk_end, n + 1, n, line, 0.0_wp)
  contains
    !> Whether pair is one of the two-character operators.
    logical function is_two(pair)
      character(len=2), intent(in) :: pair
      character(len=2), parameter :: ops(10) = ['<=', '>=', '==', '!=', '&&', '||', '+=', &
        '-=', '*=', '/=']
      is_two = any(ops == pair)
    end function is_two

    !> s holds no control character but tab, line feed, carriage return and form feed
    !! (high bytes allowed when high).
    logical function plain(s, high)
      character(len=*), intent(in) :: s
      logical, intent(in) :: high
      integer :: m, b, ln
      plain = .true.
      ln = line
      do m = 1, len(s)
        b = ichar(s(m:m))
        if (b == 10) ln = ln + 1
        if (b == 13 .and. m < len(s)) then
          if (s(m + 1:m + 1) /= achar(10)) ln = ln + 1
        end if
        if ((b < 32 .and. b /= 9 .and. b /= 10 .and. b /= 13 .and. b /= 12) .or. b == 127 &
          .or. (b > 127 .and. .not. high)) then
          plain = .false.
          call fail_at(p, ln, 'byte '//itoa(b)//' is not plain text: a .geo script is '// &
            'ASCII text (UTF-8 only in comments and strings)')
          return
        end if
      end do
    end function plain
  end subroutine tokenize

  !> Where a number that starts at i of t ends (one past its last character): digits, an
  !! optional '.' and digits, an optional exponent e or E, a sign and digits (gmsh's lexer:
  !! 12, 1.5, .5, 1., 1e-3, 1.5E+3; an 'e' without digits after it is not part of it).
  pure integer function number_end(t, i) result(j)
    character(len=*), intent(in) :: t
    integer, intent(in) :: i
    integer :: n, k
    n = len(t)
    j = i
    do while (j <= n)
      if (.not. is_digit(t(j:j))) exit
      j = j + 1
    end do
    if (j <= n) then
      if (t(j:j) == '.') then
        j = j + 1
        do while (j <= n)
          if (.not. is_digit(t(j:j))) exit
          j = j + 1
        end do
      end if
    end if
    if (j >= n) return
    if (scan(t(j:j), 'eE') == 0) return
    k = j + 1
    if (scan(t(k:k), '+-') > 0 .and. k < n) k = k + 1
    if (.not. is_digit(t(k:k))) return
    j = k
    do while (j <= n)
      if (.not. is_digit(t(j:j))) exit
      j = j + 1
    end do
  end function number_end

  !> The line ends in s: LF, CR LF (one) and CR alone.
  pure integer function count_lf(s)
    character(len=*), intent(in) :: s
    integer :: m
    count_lf = 0
    do m = 1, len(s)
      if (s(m:m) == achar(10)) then
        count_lf = count_lf + 1
      else if (s(m:m) == achar(13)) then
        if (m == len(s)) then
          count_lf = count_lf + 1
        else if (s(m + 1:m + 1) /= achar(10)) then
          count_lf = count_lf + 1
        end if
      end if
    end do
  end function count_lf

  pure logical function is_digit(ch)
    character, intent(in) :: ch
    is_digit = ch >= '0' .and. ch <= '9'
  end function is_digit

  pure logical function is_alpha(ch)
    character, intent(in) :: ch
    is_alpha = (ch >= 'a' .and. ch <= 'z') .or. (ch >= 'A' .and. ch <= 'Z') .or. ch == '_'
  end function is_alpha

  subroutine add_token(p, kind, a, b, line, v)
    type(parser_t), intent(inout) :: p
    integer, intent(in) :: kind, a, b, line
    real(wp), intent(in) :: v
    if (p%nt == size(p%tk)) then
      call grow_int(p%tk)
      call grow_int(p%ta)
      call grow_int(p%tb)
      call grow_int(p%tl)
      call grow_real(p%tv)
    end if
    p%nt = p%nt + 1
    p%tk(p%nt) = kind
    p%ta(p%nt) = a
    p%tb(p%nt) = b
    p%tl(p%nt) = line
    p%tv(p%nt) = v
  end subroutine add_token

  subroutine grow_int(a)
    integer, allocatable, intent(inout) :: a(:)
    integer, allocatable :: t(:)
    allocate(t(2*size(a)))
    t(1:size(a)) = a
    call move_alloc(t, a)
  end subroutine grow_int

  subroutine grow_real(a)
    real(wp), allocatable, intent(inout) :: a(:)
    real(wp), allocatable :: t(:)
    allocate(t(2*size(a)))
    t(1:size(a)) = a
    call move_alloc(t, a)
  end subroutine grow_real

  subroutine grow_logical(a)
    logical, allocatable, intent(inout) :: a(:)
    logical, allocatable :: t(:)
    allocate(t(2*size(a)))
    t(1:size(a)) = a
    t(size(a) + 1:) = .false.
    call move_alloc(t, a)
  end subroutine grow_logical

  ! ------------------------------------------------------------------ cursor

  !> The current token's text.
  function tok(p) result(t)
    type(parser_t), intent(in) :: p
    character(len=:), allocatable :: t
    t = p%text(p%ta(p%k):p%tb(p%k))
  end function tok

  logical function at_op(p, s)
    type(parser_t), intent(in) :: p
    character(len=*), intent(in) :: s
    at_op = .false.
    if (p%tk(p%k) == tk_op) at_op = p%text(p%ta(p%k):p%tb(p%k)) == s
  end function at_op

  logical function at_name(p, s)
    type(parser_t), intent(in) :: p
    character(len=*), intent(in) :: s
    at_name = .false.
    if (p%tk(p%k) == tk_name) at_name = p%text(p%ta(p%k):p%tb(p%k)) == s
  end function at_name

  !> Whether the token after the current one is operator s.
  logical function next_op(p, s)
    type(parser_t), intent(in) :: p
    character(len=*), intent(in) :: s
    next_op = .false.
    if (p%k < p%nt) then
      if (p%tk(p%k + 1) == tk_op) next_op = p%text(p%ta(p%k + 1):p%tb(p%k + 1)) == s
    end if
  end function next_op

  subroutine advance(p)
    type(parser_t), intent(inout) :: p
    if (p%k < p%nt) p%k = p%k + 1
  end subroutine advance

  !> The current token for a message: a number, a name, an operator or the end.
  function shown(p) result(t)
    type(parser_t), intent(in) :: p
    character(len=:), allocatable :: t
    select case (p%tk(p%k))
    case (tk_end)
      t = 'the end of the script'
    case (tk_str)
      t = 'a string'
    case default
      t = "'"//p%text(p%ta(p%k):min(p%tb(p%k), p%ta(p%k) + 39))//"'"
    end select
  end function shown

  subroutine expect(p, s, what)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: s, what
    if (len(p%msg) > 0) return
    if (at_op(p, s)) then
      call advance(p)
    else
      call fail(p, "expected '"//s//"' "//what//", found "//shown(p))
    end if
  end subroutine expect

  subroutine fail(p, msg)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: msg
    call fail_at(p, p%tl(p%k), msg)
  end subroutine fail

  subroutine fail_at(p, line, msg)
    type(parser_t), intent(inout) :: p
    integer, intent(in) :: line
    character(len=*), intent(in) :: msg
    integer :: j
    if (len(p%msg) > 0) return
    if (msg(1:1) == '@') then
      ! a message about a deck number: '@geo_names name ' first (geo_parse takes it off)
      j = index(msg(12:), ' ') + 11
      p%msg = msg(1:j)//'line '//itoa(line)//': '//msg(j + 1:)
    else
      p%msg = 'line '//itoa(line)//': '//msg
    end if
  end subroutine fail_at

  ! ------------------------------------------------------------------ statements

  !> One statement; active is .false. inside a branch not taken (read, but it does nothing).
  recursive subroutine statement(p, active)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    character(len=:), allocatable :: w
    if (len(p%msg) > 0) return
    if (at_op(p, ';')) then
      call advance(p)
      return
    end if
    if (p%tk(p%k) /= tk_name) then
      call fail(p, 'a statement cannot start with '//shown(p)//'; the subset: '//subset_words)
      return
    end if
    w = tok(p)
    select case (w)
    case ('If')
      call if_block(p, active)
    case ('Point', 'Line', 'Circle', 'Ellipse', 'Spline', 'BSpline', 'Curve', 'Plane', &
      'Surface', 'Volume')
      call entity(p, active)
    case ('Physical')
      call physical(p, active)
    case ('Field')
      call field_statement(p, active)
    case ('Background')
      call background(p, active)
    case ('Mesh')
      call mesh_option(p, active)
    case ('ElseIf', 'Else', 'EndIf')
      call fail(p, "'"//w//"' without an If before it")
    case default
      if (next_op(p, '.') .and. index(option_categories, ' '//w//' ') > 0) then
        call fail(p, "'"//w//".' options are outside the subset mfcd reads: they change "// &
          "gmsh itself (its files, logs, output and interpreter), not the model; a script "// &
          "may set Mesh.* options only")
      else if (is_gmsh_word(p, w)) then
        call fail(p, "'"//w//"' is a gmsh command or function outside the subset mfcd "// &
          "reads, which is "//subset_words)
      else if (next_op(p, '=') .or. next_op(p, '+=') .or. next_op(p, '-=') .or. &
        next_op(p, '*=') .or. next_op(p, '/=')) then
        call assignment(p, active)
      else if (next_op(p, '[') .or. next_op(p, '(')) then
        call fail(p, "'"//w//"': lists and list elements are outside the subset mfcd "// &
          "reads (give each number its own name)")
      else
        call fail(p, "'"//w//"' is not a statement of the subset mfcd reads (a variable "// &
          "needs '= value;'); the subset: "//subset_words)
      end if
    end select
  end subroutine statement

  !> name = expr; (or +=, -=, *=, /=)
  subroutine assignment(p, active)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    character(len=:), allocatable :: name, op
    integer :: v, line
    logical :: found
    real(wp) :: x
    name = tok(p)
    line = p%tl(p%k)
    call advance(p)
    op = tok(p)
    call advance(p)
    x = expression(p, active)
    call expect(p, ';', 'after the value')
    if (len(p%msg) > 0) return
    v = p%vars%get(name, found)
    if (found) p%vused(v) = .true.
    if (.not. active) then
      if (.not. found) v = new_variable(p, name)
      p%vused(v) = .true.
      return
    end if
    if (found) found = p%vdef(v)
    if (op /= '=' .and. .not. found) then
      call fail_at(p, line, "'"//name//"' is changed with "//op//" before it has a value")
      return
    end if
    if (found) then
      if (p%vdeck(v) .and. .not. p%vread(v)) then
        call fail_at(p, line, "@geo_names "//name//" sets '"//name//"' before it reads it, "// &
          "so the deck's value would be ignored: remove '"//name//"' from geo_names, or "// &
          "make the script keep a caller's value (If (!Exists("//name//")) "//name// &
          " = ...; EndIf)")
        return
      end if
    else if (v == 0) then
      v = new_variable(p, name)
    end if
    select case (op)
    case ('=')
      p%vval(v) = x
    case ('+=')
      p%vval(v) = p%vval(v) + x
    case ('-=')
      p%vval(v) = p%vval(v) - x
    case ('*=')
      p%vval(v) = p%vval(v)*x
    case ('/=')
      if (x == 0.0_wp) then
        call fail_at(p, line, 'division by zero')
        return
      end if
      p%vval(v) = p%vval(v)/x
    end select
    if (.not. ieee_is_finite(p%vval(v))) call fail_at(p, line, "'"//name//"' is not a "// &
      "finite number")
    p%vdef(v) = .true.
    p%vread(v) = .true.
    p%vused(v) = .true.
  end subroutine assignment

  integer function new_variable(p, name) result(v)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: name
    if (.not. allocated(p%vval)) then
      allocate(p%vval(64))
      allocate(p%vdef(64), p%vdeck(64), p%vread(64), p%vused(64), source=.false.)
    end if
    if (p%nvar == size(p%vval)) then
      call grow_real(p%vval)
      call grow_logical(p%vdef)
      call grow_logical(p%vdeck)
      call grow_logical(p%vread)
      call grow_logical(p%vused)
    end if
    p%nvar = p%nvar + 1
    v = p%nvar
    p%vval(v) = 0.0_wp
    p%vdef(v) = .false.
    p%vdeck(v) = .false.
    p%vread(v) = .false.
    p%vused(v) = .false.
    call p%vars%put(name, v)
  end function new_variable

  !> If (c) ... [ElseIf (c) ...] [Else ...] EndIf
  recursive subroutine if_block(p, active)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    logical :: done, taken
    real(wp) :: c
    integer :: line
    line = p%tl(p%k)
    p%depth = p%depth + 1
    if (p%depth > max_depth) then
      call fail(p, 'If blocks nest more than '//itoa(max_depth)//' deep')
      return
    end if
    call advance(p)
    call expect(p, '(', 'after If')
    c = expression(p, active)
    call expect(p, ')', 'after the condition')
    taken = active .and. c /= 0.0_wp
    done = taken
    call branch(taken)
    do while (len(p%msg) == 0 .and. at_name(p, 'ElseIf'))
      call advance(p)
      call expect(p, '(', 'after ElseIf')
      c = expression(p, active .and. .not. done)
      call expect(p, ')', 'after the condition')
      taken = active .and. .not. done .and. c /= 0.0_wp
      done = done .or. taken
      call branch(taken)
    end do
    if (len(p%msg) == 0 .and. at_name(p, 'Else')) then
      call advance(p)
      call branch(active .and. .not. done)
    end if
    if (len(p%msg) > 0) return
    if (.not. at_name(p, 'EndIf')) then
      call fail_at(p, line, 'this If has no EndIf')
      return
    end if
    call advance(p)
    p%depth = p%depth - 1
  contains
    recursive subroutine branch(on)
      logical, intent(in) :: on
      do while (len(p%msg) == 0)
        if (p%tk(p%k) == tk_end) exit
        if (at_name(p, 'ElseIf') .or. at_name(p, 'Else') .or. at_name(p, 'EndIf')) exit
        call statement(p, on)
      end do
    end subroutine branch
  end subroutine if_block

  !> Point, Line, Circle, Ellipse, Spline, BSpline, Curve Loop, Line Loop, Plane Surface,
  !! Surface, Surface Loop, Volume: kind(tag) = {list};
  subroutine entity(p, active)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    character(len=:), allocatable :: w, what
    integer :: op, cls, tag, line, n, j, need_cls, nmin, nmax
    real(wp), allocatable :: vals(:)
    integer, allocatable :: ids(:)
    line = p%tl(p%k)
    w = tok(p)
    call advance(p)
    select case (w)
    case ('Curve', 'Line')
      if (at_name(p, 'Loop')) then
        call advance(p)
        op = op_curve_loop
        what = w//' Loop'
      else if (w == 'Line') then
        op = op_line
        what = w
      else
        call fail(p, "'Curve' is read as 'Curve Loop' only (a curve is a Line, Circle, "// &
          "Ellipse, Spline or BSpline)")
        return
      end if
    case ('Plane')
      if (.not. at_name(p, 'Surface')) then
        call fail(p, "expected 'Plane Surface'")
        return
      end if
      call advance(p)
      op = op_plane_surface
      what = 'Plane Surface'
    case ('Surface')
      if (at_name(p, 'Loop')) then
        call advance(p)
        op = op_surface_loop
        what = 'Surface Loop'
      else
        op = op_surface
        what = 'Surface'
      end if
    case ('Point')
      op = op_point
      what = w
    case ('Circle')
      op = op_circle
      what = w
    case ('Ellipse')
      op = op_ellipse
      what = w
    case ('Spline')
      op = op_spline
      what = w
    case ('BSpline')
      op = op_bspline
      what = w
    case default
      op = op_volume
      what = w
    end select
    call expect(p, '(', 'after '//what)
    tag = tag_value(p, expression(p, active), active, what)
    call expect(p, ')', 'after the tag of the '//what)
    call expect(p, '=', 'after '//what//'(tag)')
    call list(p, active, vals)
    call expect(p, ';', 'after the '//what)
    if (len(p%msg) > 0 .or. .not. active) return
    n = size(vals)
    call entity_rules(op, cls, nmin, nmax, need_cls)
    if (n < nmin .or. n > nmax) then
      if (nmin == nmax) then
        call fail_at(p, line, what//' needs '//itoa(nmin)//' values, not '//itoa(n))
      else if (nmax < max_list) then
        call fail_at(p, line, what//' needs '//itoa(nmin)//' to '//itoa(nmax)// &
          ' values, not '//itoa(n))
      else
        call fail_at(p, line, what//' needs at least '//itoa(nmin)//' values')
      end if
      return
    end if
    call check_new(p, cls, tag, what, line)
    if (len(p%msg) > 0) return
    if (op == op_point) then
      if (n == 4) then
        if (vals(4) < 0.0_wp) then
          call fail_at(p, line, 'the mesh size of Point '//itoa(tag)//' is negative')
          return
        end if
      end if
      call add_op(p%m, op, tag, line, 0, [integer ::], [vals, (0.0_wp, j = n + 1, 4)])
    else
      allocate(ids(n))
      do j = 1, n
        ids(j) = tag_value(p, vals(j), .true., 'reference', signed=op == op_curve_loop)
        if (len(p%msg) > 0) return
        call check_exists(p, need_cls, abs(ids(j)), what//' '//itoa(tag), line)
        if (len(p%msg) > 0) return
      end do
      if (op == op_ellipse .and. n == 3) ids = [ids(1), ids(2), ids(1), ids(3)]
      if (op == op_line) then
        if (ids(1) == ids(2)) then
          call fail_at(p, line, 'Line '//itoa(tag)//' starts and ends at Point '// &
            itoa(ids(1)))
          return
        end if
      end if
      call add_op(p%m, op, tag, line, 0, ids, [real(wp) ::])
      if (op == op_plane_surface .or. op == op_surface) p%m%nsurfaces = p%m%nsurfaces + 1
    end if
    call p%ent(cls)%put(tag, p%m%nops)
    p%maxtag(cls) = max(p%maxtag(cls), tag)
  end subroutine entity

  !> What a geometry call of kind op defines (its class), how many values it takes, and
  !! the class of the entities it names (0 for a point's coordinates).
  pure subroutine entity_rules(op, cls, nmin, nmax, need_cls)
    integer, intent(in) :: op
    integer, intent(out) :: cls, nmin, nmax, need_cls
    cls = ent_curve
    nmin = 1
    nmax = max_list
    need_cls = ent_point
    select case (op)
    case (op_point)
      cls = ent_point
      nmin = 3
      nmax = 4
      need_cls = 0
    case (op_line)
      nmin = 2
      nmax = 2
    case (op_circle)
      nmin = 3
      nmax = 3
    case (op_ellipse)
      nmin = 3
      nmax = 4
    case (op_spline, op_bspline)
      nmin = 2
    case (op_curve_loop)
      cls = ent_loop
      need_cls = ent_curve
    case (op_plane_surface, op_surface)
      cls = ent_surface
      need_cls = ent_loop
    case (op_surface_loop)
      cls = ent_shell
      need_cls = ent_surface
    case default
      cls = ent_volume
      need_cls = ent_shell
    end select
  end subroutine entity_rules

  !> Physical Point|Curve|Line|Surface|Volume(tag | "name" [, tag]) = {list}; read and
  !! checked; mfcd takes every node and triangle, so a physical group changes nothing of
  !! the body and is not passed to gmsh (its number still counts for newreg, as in gmsh).
  subroutine physical(p, active)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    character(len=:), allocatable :: w
    integer :: cls, tag, line, j, id
    real(wp), allocatable :: vals(:)
    logical :: named
    line = p%tl(p%k)
    call advance(p)
    w = ''
    if (p%tk(p%k) == tk_name) w = tok(p)
    select case (w)
    case ('Point')
      cls = ent_point
    case ('Curve', 'Line')
      cls = ent_curve
    case ('Surface')
      cls = ent_surface
    case ('Volume')
      cls = ent_volume
    case default
      call fail(p, "expected Physical Point, Curve, Line, Surface or Volume")
      return
    end select
    call advance(p)
    call expect(p, '(', 'after Physical '//w)
    named = p%tk(p%k) == tk_str
    tag = 0
    if (named) then
      call advance(p)
      if (at_op(p, ',')) then
        call advance(p)
        tag = tag_value(p, expression(p, active), active, 'Physical '//w)
      end if
    else
      tag = tag_value(p, expression(p, active), active, 'Physical '//w)
    end if
    call expect(p, ')', 'after the tag of the physical group')
    call expect(p, '=', 'after Physical '//w//'(...)')
    call list(p, active, vals)
    call expect(p, ';', 'after the physical group')
    if (len(p%msg) > 0 .or. .not. active) return
    if (tag == 0) tag = p%maxtag(ent_physical) + 1
    call check_new(p, ent_physical, tag, 'Physical '//w, line)
    do j = 1, size(vals)
      if (len(p%msg) > 0) return
      id = tag_value(p, vals(j), .true., 'reference', signed=.true.)
      if (len(p%msg) == 0) call check_exists(p, cls, abs(id), 'Physical '//w//' '// &
        itoa(tag), line)
    end do
    if (len(p%msg) > 0) return
    call p%ent(ent_physical)%put(tag, 0)
    p%maxtag(ent_physical) = max(p%maxtag(ent_physical), tag)
  end subroutine physical

  !> Field[n] = Type;  Field[n].Option = value | {list};
  subroutine field_statement(p, active)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    integer :: tag, line, kind, opt, j, ftype, fo
    character(len=:), allocatable :: w, tname, okind
    character(len=word_len) :: parts(3)
    real(wp), allocatable :: vals(:)
    real(wp) :: x
    logical :: found, is_list
    line = p%tl(p%k)
    call advance(p)
    call expect(p, '[', "after Field (Field[1] = Distance;)")
    tag = tag_value(p, expression(p, active), active, 'Field')
    call expect(p, ']', 'after the field tag')
    if (len(p%msg) > 0) return
    if (at_op(p, '=')) then
      call advance(p)
      if (p%tk(p%k) /= tk_name) then
        call fail(p, 'expected a field type after Field['//itoa(tag)//'] =')
        return
      end if
      w = tok(p)
      kind = 0
      do j = 1, size(field_types)
        if (w == trim(field_types(j))) kind = j
      end do
      if (kind == 0) then
        if (is_gmsh_word(p, w) .or. len(w) <= 40) then
          call fail(p, "field type '"//w//"' is outside the subset mfcd reads (it reads "// &
            "Distance, Threshold, Min, Max, Box, Ball, Cylinder, Constant, Restrict)")
        else
          call fail(p, "this field type is outside the subset mfcd reads (it reads "// &
            "Distance, Threshold, Min, Max, Box, Ball, Cylinder, Constant, Restrict)")
        end if
        return
      end if
      call advance(p)
      call expect(p, ';', 'after the field type')
      if (len(p%msg) > 0 .or. .not. active) return
      call check_new(p, ent_field, tag, 'Field', line)
      if (len(p%msg) > 0) return
      call add_op(p%m, op_field, tag, line, kind, [integer ::], [real(wp) ::])
      call p%ent(ent_field)%put(tag, p%m%nops)
      call p%field_kind%put(tag, kind)
      p%maxtag(ent_field) = max(p%maxtag(ent_field), tag)
      return
    end if
    call expect(p, '.', 'or = after Field['//itoa(tag)//']')
    if (len(p%msg) > 0) return
    if (p%tk(p%k) /= tk_name) then
      call fail(p, 'expected a field option after Field['//itoa(tag)//'].')
      return
    end if
    w = tok(p)
    call advance(p)
    call expect(p, '=', 'after the field option')
    is_list = at_op(p, '{')
    if (is_list) then
      call list(p, active, vals)
    else
      x = expression(p, active)
      vals = [x]
    end if
    call expect(p, ';', 'after the field option')
    if (len(p%msg) > 0 .or. .not. active) return
    ftype = p%field_kind%get(tag, found)
    if (.not. found) then
      call fail_at(p, line, 'Field['//itoa(tag)//'] is set before it is defined '// &
        '(Field['//itoa(tag)//'] = Distance; first)')
      return
    end if
    tname = trim(field_types(ftype))
    opt = 0
    do fo = 1, size(field_options)
      call entry_words(field_options(fo), parts)
      if (trim(parts(1)) == tname .and. trim(parts(2)) == w) then
        opt = fo
        okind = kind_of(parts(3))
        exit
      end if
    end do
    if (opt == 0) then
      call fail_at(p, line, "option '"//w(1:min(len(w), 40))//"' of a "//tname// &
        " field is outside the subset mfcd reads ("//field_option_list(tname)//")")
      return
    end if
    if (okind(1:1) == 'L') then
      if (.not. is_list) then
        call fail_at(p, line, 'Field['//itoa(tag)//'].'//w//' takes a list: {...}')
        return
      end if
      do j = 1, size(vals)
        if (len(p%msg) > 0) return
        if (tag_value(p, vals(j), .true., w) == 0) return
      end do
      if (size(vals) > max_list) then
        call fail_at(p, line, 'Field['//itoa(tag)//'].'//w//' holds more than '// &
          itoa(max_list)//' tags')
        return
      end if
      call add_op(p%m, op_field_list, tag, line, opt, [integer ::], vals)
    else
      if (is_list) then
        call fail_at(p, line, 'Field['//itoa(tag)//'].'//w//' takes one number, not a list')
        return
      end if
      call check_value(p, okind, vals(1), 'Field['//itoa(tag)//'].'//w, line)
      if (len(p%msg) > 0) return
      call add_op(p%m, op_field_number, tag, line, opt, [integer ::], vals)
    end if
  end subroutine field_statement

  !> The options of a field type, for messages.
  function field_option_list(tname) result(t)
    character(len=*), intent(in) :: tname
    character(len=:), allocatable :: t
    character(len=word_len) :: parts(3)
    integer :: fo
    t = ''
    do fo = 1, size(field_options)
      call entry_words(field_options(fo), parts)
      if (trim(parts(1)) /= tname) cycle
      if (len(t) > 0) t = t//', '
      t = t//trim(parts(2))
    end do
  end function field_option_list

  !> Background Field = n;
  subroutine background(p, active)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    integer :: tag, line
    line = p%tl(p%k)
    call advance(p)
    if (.not. at_name(p, 'Field')) then
      call fail(p, "expected 'Background Field = n;'")
      return
    end if
    call advance(p)
    call expect(p, '=', "after Background Field")
    tag = tag_value(p, expression(p, active), active, 'Background Field')
    call expect(p, ';', 'after Background Field')
    if (len(p%msg) > 0 .or. .not. active) return
    p%background = tag
    p%background_line = line
    call add_op(p%m, op_background, tag, line, 0, [integer ::], [real(wp) ::])
  end subroutine background

  !> Mesh.Option = value;
  subroutine mesh_option(p, active)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    integer :: line, mo, opt
    character(len=:), allocatable :: w, okind
    character(len=word_len) :: parts(3)
    real(wp) :: x
    line = p%tl(p%k)
    call advance(p)
    call expect(p, '.', "after Mesh (Mesh.Algorithm = 6;)")
    if (len(p%msg) > 0) return
    if (p%tk(p%k) /= tk_name) then
      call fail(p, 'expected a Mesh option after Mesh.')
      return
    end if
    w = tok(p)
    opt = 0
    do mo = 1, size(mesh_options)
      call entry_words(mesh_options(mo), parts)
      if (trim(parts(1)) == w) then
        opt = mo
        okind = kind_of(parts(2))
        exit
      end if
    end do
    if (opt == 0) then
      call fail(p, "Mesh."//w(1:min(len(w), 40))//" is outside the subset mfcd reads (it "// &
        "reads Mesh."//mesh_option_list()//")")
      return
    end if
    call advance(p)
    call expect(p, '=', 'after Mesh.'//w)
    if (at_op(p, '{')) then
      call fail(p, 'Mesh.'//w//' takes one number, not a list')
      return
    end if
    x = expression(p, active)
    call expect(p, ';', 'after Mesh.'//w)
    if (len(p%msg) > 0 .or. .not. active) return
    call check_value(p, okind, x, 'Mesh.'//w, line)
    if (len(p%msg) > 0) return
    call add_op(p%m, op_mesh_option, 0, line, opt, [integer ::], [x])
  end subroutine mesh_option

  function mesh_option_list() result(t)
    character(len=:), allocatable :: t
    character(len=word_len) :: parts(3)
    integer :: mo
    t = ''
    do mo = 1, size(mesh_options)
      call entry_words(mesh_options(mo), parts)
      if (len(t) > 0) t = t//', Mesh.'
      t = t//trim(parts(1))
    end do
  end function mesh_option_list

  !> A value of the kind of a field or Mesh option table entry (their headers say what).
  subroutine check_value(p, kind, x, what, line)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: kind, what
    real(wp), intent(in) :: x
    integer, intent(in) :: line
    character(len=:), allocatable :: need
    logical :: whole
    integer :: iv
    need = ''
    whole = x == aint(x) .and. abs(x) < 2.0_wp**31
    ! nint only of a whole number in range (an invalid conversion traps in Debug builds)
    iv = 0
    if (whole) iv = nint(x)
    select case (kind)
    case ('D')
      if (x < 0.0_wp) need = 'a number >= 0'
    case ('P')
      if (x <= 0.0_wp) need = 'a number > 0'
    case ('B')
      if (x /= 0.0_wp .and. x /= 1.0_wp) need = '0 or 1'
    case ('I')
      if (.not. whole .or. x < 1.0_wp .or. x > 100000.0_wp) need = &
        'a whole number from 1 to 100000'
    case ('F')
      if (.not. whole .or. x < 1.0_wp) need = "a field's tag (a whole number from 1)"
    case ('C')
      if (.not. whole .or. x < 0.0_wp .or. x > 10000.0_wp) need = &
        'a whole number from 0 to 10000'
    case ('X')
      if (.not. whole .or. all(iv /= [-3, -2, 0, 1, 2])) need = &
        'one of -3, -2, 0, 1, 2'
    case ('A2')
      if (.not. whole .or. all(iv /= [1, 2, 3, 5, 6, 7, 8, 9, 11])) need = &
        "one of gmsh's 2D algorithms 1, 2, 3, 5, 6, 7, 8, 9, 11"
    case ('A3')
      if (.not. whole .or. all(iv /= [1, 3, 4, 7, 9, 10])) need = &
        "one of gmsh's 3D algorithms 1, 3, 4, 7, 9, 10"
    case ('S')
      if (.not. whole .or. x < 0.0_wp .or. x > 100.0_wp) need = &
        'a whole number from 0 to 100'
    case ('U')
      if (x < 0.0_wp .or. x > 1.0_wp) need = 'a number from 0 to 1'
    case ('R')
      if (.not. whole .or. x < 0.0_wp) need = 'a whole number >= 0'
    case ('O')
      if (x /= 1.0_wp) need = '1: mfcd takes linear triangles'
    end select
    if (len(need) > 0) call fail_at(p, line, what//' = '//rtoa(x)//': give '//need)
  end subroutine check_value

  ! ------------------------------------------------------------------ entities

  !> A tag: a whole number 1 .. 2^31 - 1 (or its negative where signed). 0 when inactive or
  !! wrong (then msg says why).
  integer function tag_value(p, x, active, what, signed) result(tag)
    type(parser_t), intent(inout) :: p
    real(wp), intent(in) :: x
    logical, intent(in) :: active
    character(len=*), intent(in) :: what
    logical, intent(in), optional :: signed
    logical :: neg_ok
    tag = 0
    if (.not. active .or. len(p%msg) > 0) return
    neg_ok = .false.
    if (present(signed)) neg_ok = signed
    if (x /= aint(x) .or. abs(x) > real(max_tag, wp) .or. x == 0.0_wp .or. &
      (x < 0.0_wp .and. .not. neg_ok)) then
      call fail(p, 'the '//what//' tag '//rtoa(x)//' is not a whole number from 1 to '// &
        itoa(max_tag))
      return
    end if
    tag = int(x)
  end function tag_value

  subroutine check_new(p, cls, tag, what, line)
    type(parser_t), intent(inout) :: p
    integer, intent(in) :: cls, tag, line
    character(len=*), intent(in) :: what
    integer :: k
    logical :: found
    k = p%ent(cls)%get(tag, found)
    if (found) then
      if (k > 0) then
        call fail_at(p, line, what//' '//itoa(tag)//' is defined twice (first at line '// &
          itoa(p%m%line(k))//')')
      else
        call fail_at(p, line, what//' '//itoa(tag)//' is defined twice')
      end if
    end if
  end subroutine check_new

  subroutine check_exists(p, cls, tag, what, line)
    type(parser_t), intent(inout) :: p
    integer, intent(in) :: cls, tag, line
    character(len=*), intent(in) :: what
    integer :: k
    logical :: found
    k = p%ent(cls)%get(tag, found)
    if (.not. found) call fail_at(p, line, what//' names '//trim(ent_names(cls))//' '// &
      itoa(tag)//', which is not defined before it')
  end subroutine check_exists

  !> After the whole script: every field a field or the background names exists, fields
  !! name their entities, and no field depends on itself.
  subroutine check_references(p)
    type(parser_t), intent(inout) :: p
    integer :: k, j, cls, tag, ne, parent
    character(len=word_len) :: parts(3)
    character(len=:), allocatable :: okind
    logical :: found
    integer, allocatable :: state(:), head(:), next(:), child(:), eline(:)
    do k = 1, p%m%nops
      if (len(p%msg) > 0) return
      if (p%m%kind(k) /= op_field_number .and. p%m%kind(k) /= op_field_list) cycle
      call entry_words(field_options(p%m%sub(k)), parts)
      okind = kind_of(parts(3))
      select case (okind)
      case ('F', 'LF')
        cls = ent_field
      case ('L0')
        cls = ent_point
      case ('L1')
        cls = ent_curve
      case ('L2')
        cls = ent_surface
      case ('L3')
        cls = ent_volume
      case default
        cycle
      end select
      do j = p%m%r0(k), p%m%r0(k) + p%m%nr(k) - 1
        tag = int(abs(p%m%reals(j)))
        call check_exists_anywhere(cls, tag, 'Field['//itoa(p%m%tag(k))//'].'// &
          trim(parts(2)), p%m%line(k))
        if (len(p%msg) > 0) return
      end do
    end do
    if (p%background /= 0) then
      j = p%ent(ent_field)%get(p%background, found)
      if (.not. found) then
        call fail_at(p, p%background_line, 'Background Field = '//itoa(p%background)// &
          ' names no field')
        return
      end if
    end if
    ! no field may depend on itself (gmsh would recurse until its stack overflows): the
    ! edges field -> field it reads, as linked lists by the reading field's definition
    allocate(head(p%m%nops), source=0)
    allocate(state(p%m%nops), source=0)
    allocate(next(p%m%nreals), child(p%m%nreals), eline(p%m%nreals))
    ne = 0
    do k = 1, p%m%nops
      if (p%m%kind(k) /= op_field_number .and. p%m%kind(k) /= op_field_list) cycle
      call entry_words(field_options(p%m%sub(k)), parts)
      okind = kind_of(parts(3))
      if (okind /= 'F' .and. okind /= 'LF') cycle
      parent = p%ent(ent_field)%get(p%m%tag(k), found)
      do j = p%m%r0(k), p%m%r0(k) + p%m%nr(k) - 1
        ne = ne + 1
        child(ne) = p%ent(ent_field)%get(int(p%m%reals(j)), found)
        eline(ne) = p%m%line(k)
        next(ne) = head(parent)
        head(parent) = ne
      end do
    end do
    do k = 1, p%m%nops
      if (p%m%kind(k) == op_field .and. len(p%msg) == 0) call visit(k, p%m%line(k))
    end do
  contains
    subroutine check_exists_anywhere(c, t, what, line)
      integer, intent(in) :: c, t, line
      character(len=*), intent(in) :: what
      integer :: i
      logical :: f
      i = p%ent(c)%get(t, f)
      if (.not. f) call fail_at(p, line, what//' names '//trim(ent_names(c))//' '//itoa(t)// &
        ', which is not defined')
    end subroutine check_exists_anywhere

    !> Depth-first over the fields a field reads: state 1 on the path, 2 done; line is
    !! where the option that leads here was set.
    recursive subroutine visit(fk, line)
      integer, intent(in) :: fk, line
      integer :: e
      if (state(fk) == 2 .or. len(p%msg) > 0) return
      if (state(fk) == 1) then
        call fail_at(p, line, 'Field['//itoa(p%m%tag(fk))//'] depends on itself '// &
          '(through InField or FieldsList)')
        return
      end if
      state(fk) = 1
      e = head(fk)
      do while (e /= 0)
        call visit(child(e), eline(e))
        e = next(e)
      end do
      state(fk) = 2
    end subroutine visit
  end subroutine check_references

  ! ------------------------------------------------------------------ lists

  !> {a, b, c:d, e:f:g, ...} into vals (ranges as gmsh expands them).
  subroutine list(p, active, vals)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    real(wp), allocatable, intent(out) :: vals(:)
    real(wp) :: a, b, s, d
    integer :: n
    allocate(vals(8))
    n = 0
    call expect(p, '{', 'before the list')
    if (len(p%msg) > 0) return
    if (at_op(p, '}')) then
      call advance(p)
      vals = vals(1:0)
      return
    end if
    do
      a = expression(p, active)
      if (len(p%msg) > 0) return
      if (at_op(p, ':')) then
        call advance(p)
        b = expression(p, active)
        s = merge(1.0_wp, -1.0_wp, b >= a)
        if (at_op(p, ':')) then
          call advance(p)
          s = expression(p, active)
        end if
        if (len(p%msg) > 0) return
        if (active) then
          if (s == 0.0_wp .or. (b - a)*s < 0.0_wp) then
            call fail(p, 'the range '//rtoa(a)//':'//rtoa(b)//':'//rtoa(s)//' is empty '// &
              'or endless')
            return
          end if
          if ((b - a)/s + 1.0_wp > real(max_list, wp)) then
            call fail(p, 'a list holds more than '//itoa(max_list)//' values')
            return
          end if
          ! as gmsh's loop: d = a, a + s, ... while d has not passed b
          d = a
          do while ((s > 0.0_wp .and. d <= b) .or. (s < 0.0_wp .and. d >= b))
            call push(d)
            if (len(p%msg) > 0) return
            d = d + s
          end do
        end if
      else
        call push(a)
      end if
      if (len(p%msg) > 0) return
      if (at_op(p, ',')) then
        call advance(p)
        cycle
      end if
      exit
    end do
    call expect(p, '}', 'after the list')
    vals = vals(1:n)
  contains
    subroutine push(x)
      real(wp), intent(in) :: x
      if (n == max_list) then
        call fail(p, 'a list holds more than '//itoa(max_list)//' values')
        return
      end if
      if (p%m%nreals + n + 1 > max_values) then
        call fail(p, 'the lists hold more than '//itoa(max_values)//' values')
        return
      end if
      if (n == size(vals)) call grow_real(vals)
      n = n + 1
      vals(n) = x
    end subroutine push
  end subroutine list

  ! ------------------------------------------------------------------ expressions

  !> An expression (gmsh's FExpr): its value when active, 0 otherwise; a value that is not
  !! finite is an error.
  recursive real(wp) function expression(p, active) result(v)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    v = ternary(p, active)
    if (active .and. len(p%msg) == 0 .and. .not. ieee_is_finite(v)) then
      call fail(p, 'an expression is not a finite number')
      v = 0.0_wp
    end if
  end function expression

  !> c ? a : b (right-associative; gmsh evaluates both)
  recursive real(wp) function ternary(p, active) result(v)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    real(wp) :: a, b
    if (.not. deeper(p)) then
      v = 0.0_wp
      return
    end if
    v = binary(p, active, 1)
    if (at_op(p, '?')) then
      call advance(p)
      a = ternary(p, active)
      call expect(p, ':', "in 'condition ? a : b'")
      b = ternary(p, active)
      v = merge(a, b, v /= 0.0_wp)
    end if
    p%depth = p%depth - 1
  end function ternary

  logical function deeper(p)
    type(parser_t), intent(inout) :: p
    p%depth = p%depth + 1
    deeper = p%depth <= max_depth .and. len(p%msg) == 0
    if (p%depth > max_depth) call fail(p, 'expressions nest more than '//itoa(max_depth)// &
      ' deep')
    if (.not. deeper) p%depth = p%depth - 1
  end function deeper

  !> Binary operators by gmsh's precedence, loosest first: ||, &&, == !=, < > <= >=, + -,
  !! * / %; all left-associative.
  recursive real(wp) function binary(p, active, level) result(v)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    integer, intent(in) :: level
    character(len=:), allocatable :: op
    real(wp) :: b
    integer :: line
    if (level > 6) then
      v = unary(p, active)
      return
    end if
    v = binary(p, active, level + 1)
    do while (len(p%msg) == 0)
      if (p%tk(p%k) /= tk_op) exit
      op = tok(p)
      if (.not. at_level(op)) exit
      line = p%tl(p%k)
      call advance(p)
      b = binary(p, active, level + 1)
      if (.not. active .or. len(p%msg) > 0) cycle
      select case (op)
      case ('||')
        v = merge(1.0_wp, 0.0_wp, v /= 0.0_wp .or. b /= 0.0_wp)
      case ('&&')
        v = merge(1.0_wp, 0.0_wp, v /= 0.0_wp .and. b /= 0.0_wp)
      case ('==')
        v = merge(1.0_wp, 0.0_wp, v == b)
      case ('!=')
        v = merge(1.0_wp, 0.0_wp, v /= b)
      case ('<')
        v = merge(1.0_wp, 0.0_wp, v < b)
      case ('>')
        v = merge(1.0_wp, 0.0_wp, v > b)
      case ('<=')
        v = merge(1.0_wp, 0.0_wp, v <= b)
      case ('>=')
        v = merge(1.0_wp, 0.0_wp, v >= b)
      case ('+')
        v = v + b
      case ('-')
        v = v - b
      case ('*')
        v = v*b
      case ('/')
        if (b == 0.0_wp) then
          call fail_at(p, line, 'division by zero')
          return
        end if
        v = v/b
      case ('%')
        ! gmsh: (int)a % (int)b
        ! int of a number out of range is invalid (and traps in Debug builds)
        if (abs(v) >= 2.0_wp**31 .or. abs(b) >= 2.0_wp**31) then
          call fail_at(p, line, "the operands of % must be below 2^31")
          return
        end if
        if (int(b) == 0) then
          call fail_at(p, line, "the second operand of % is 0 as a whole number")
          return
        end if
        v = real(mod(int(v), int(b)), wp)
      end select
    end do
  contains
    logical function at_level(o)
      character(len=*), intent(in) :: o
      select case (level)
      case (1)
        at_level = o == '||'
      case (2)
        at_level = o == '&&'
      case (3)
        at_level = o == '==' .or. o == '!='
      case (4)
        at_level = o == '<' .or. o == '>' .or. o == '<=' .or. o == '>='
      case (5)
        at_level = o == '+' .or. o == '-'
      case default
        at_level = o == '*' .or. o == '/' .or. o == '%'
      end select
    end function at_level
  end function binary

  !> - + ! (prefix), binding looser than ^ (gmsh: -2^2 = -4).
  recursive real(wp) function unary(p, active) result(v)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    if (.not. deeper(p)) then
      v = 0.0_wp
      return
    end if
    if (at_op(p, '-')) then
      call advance(p)
      v = -unary(p, active)
    else if (at_op(p, '+')) then
      call advance(p)
      v = unary(p, active)
    else if (at_op(p, '!')) then
      call advance(p)
      v = merge(1.0_wp, 0.0_wp, unary(p, active) == 0.0_wp)
    else
      v = power(p, active)
    end if
    p%depth = p%depth - 1
  end function unary

  !> a ^ b, right-associative, the exponent may carry a sign (2^-1).
  recursive real(wp) function power(p, active) result(v)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    real(wp) :: b
    v = primary(p, active)
    if (at_op(p, '^')) then
      call advance(p)
      b = unary(p, active)
      if (active .and. len(p%msg) == 0) v = v**b
    end if
  end function power

  !> A number, a name, (expr), Pi, new*, Exists(name), or a function of one or two
  !! arguments (gmsh accepts ( or [ around them).
  recursive real(wp) function primary(p, active) result(v)
    type(parser_t), intent(inout) :: p
    logical, intent(in) :: active
    character(len=:), allocatable :: w, close_op
    real(wp) :: a, b
    integer :: var, line
    logical :: found
    v = 0.0_wp
    if (len(p%msg) > 0) return
    line = p%tl(p%k)
    select case (p%tk(p%k))
    case (tk_num)
      v = p%tv(p%k)
      call advance(p)
      return
    case (tk_op)
      if (at_op(p, '(')) then
        call advance(p)
        v = ternary(p, active)
        call expect(p, ')', 'to close (')
        return
      end if
      call fail(p, 'expected a value, found '//shown(p))
      return
    case (tk_name)
      continue
    case default
      call fail(p, 'expected a value, found '//shown(p))
      return
    end select
    w = tok(p)
    call advance(p)
    select case (w)
    case ('Pi')
      v = 3.141592653589793_wp
      return
    case ('newp')
      v = p%maxtag(ent_point) + 1
      return
    case ('newl', 'newc', 'newll', 'newcl', 'news', 'newsl', 'newv', 'newreg')
      ! gmsh's Geometry.OldNewReg (on by default): all of these are newreg
      v = maxval(p%maxtag([ent_curve, ent_loop, ent_surface, ent_shell, ent_volume, &
        ent_physical])) + 1
      return
    case ('newf')
      v = p%maxtag(ent_field) + 1
      return
    case ('Exists')
      if (.not. (at_op(p, '(') .or. at_op(p, '['))) then
        call fail(p, "expected Exists(name)")
        return
      end if
      close_op = merge(')', ']', at_op(p, '('))
      call advance(p)
      if (p%tk(p%k) /= tk_name) then
        call fail(p, 'expected a name in Exists(name)')
        return
      end if
      w = tok(p)
      call advance(p)
      call expect(p, close_op, 'after Exists(name')
      var = p%vars%get(w, found)
      if (found) then
        p%vused(var) = .true.
        if (active) p%vread(var) = .true.
        found = p%vdef(var)
      end if
      if (index(', '//p%tested//',', ', '//w//',') == 0 .and. len(w) <= 40) then
        if (len(p%tested) > 0) p%tested = p%tested//', '
        p%tested = p%tested//w
      end if
      v = merge(1.0_wp, 0.0_wp, found)
      return
    end select
    if (index(functions1, ' '//w//' ') > 0 .or. index(functions2, ' '//w//' ') > 0) then
      if (.not. (at_op(p, '(') .or. at_op(p, '['))) then
        call fail(p, "expected "//w//"(...)")
        return
      end if
      close_op = merge(')', ']', at_op(p, '('))
      call advance(p)
      a = ternary(p, active)
      b = 0.0_wp
      if (index(functions2, ' '//w//' ') > 0) then
        call expect(p, ',', 'between the two arguments of '//w)
        b = ternary(p, active)
      end if
      call expect(p, close_op, 'after the argument(s) of '//w)
      if (.not. active .or. len(p%msg) > 0) return
      v = apply(w, a, b)
      if (.not. ieee_is_finite(v)) call fail_at(p, line, w//' of '//rtoa(a)// &
        merge(', '//rtoa(b), '              ', index(functions2, ' '//w//' ') > 0)// &
        ' is not a finite number')
      return
    end if
    if (is_gmsh_word(p, w)) then
      call fail_at(p, line, "'"//w//"' is a gmsh command or function outside the subset "// &
        "mfcd reads, which is "//subset_words)
      return
    end if
    if (at_op(p, '(') .or. at_op(p, '[')) then
      call fail_at(p, line, "'"//w//"(...)' or '"//w//"[...]': lists, list elements and "// &
        "functions of the user are outside the subset mfcd reads")
      return
    end if
    var = p%vars%get(w, found)
    if (.not. found) var = new_variable(p, w)
    p%vused(var) = .true.
    if (.not. p%vdef(var)) then
      if (active) call fail_at(p, line, "'"//w//"' is used before it has a value")
      return
    end if
    if (active) then
      p%vread(var) = .true.
      v = p%vval(var)
    end if
  end function primary

  !> gmsh's functions (Gmsh.y, FExpr).
  real(wp) function apply(f, a, b) result(v)
    character(len=*), intent(in) :: f
    real(wp), intent(in) :: a, b
    select case (f)
    case ('Exp')
      v = exp(a)
    case ('Log')
      v = log(a)
    case ('Log10')
      v = log10(a)
    case ('Sqrt')
      v = sqrt(a)
    case ('Sin')
      v = sin(a)
    case ('Asin', 'ArcSin')
      v = asin(a)
    case ('Cos')
      v = cos(a)
    case ('Acos', 'ArcCos')
      v = acos(a)
    case ('Tan')
      v = tan(a)
    case ('Atan', 'ArcTan')
      v = atan(a)
    case ('Atan2', 'ArcTan2')
      v = atan2(a, b)
    case ('Sinh')
      v = sinh(a)
    case ('Cosh')
      v = cosh(a)
    case ('Tanh')
      v = tanh(a)
    case ('Fabs', 'Abs')
      v = abs(a)
    case ('Floor')
      v = floor_real(a)
    case ('Ceil')
      v = -floor_real(-a)
    case ('Round')
      v = floor_real(a + 0.5_wp)
    case ('Step')
      v = merge(0.0_wp, 1.0_wp, a < 0.0_wp)
    case ('Fmod', 'Modulo')
      v = mod(a, b)
    case ('Hypot')
      v = sqrt(a*a + b*b)
    case ('Max')
      v = max(a, b)
    case ('Min')
      v = min(a, b)
    case default
      v = 0.0_wp
    end select
  end function apply

  !> floor of a real, as a real (no integer overflow for large values).
  elemental real(wp) function floor_real(a)
    real(wp), intent(in) :: a
    floor_real = aint(a)
    if (floor_real > a) floor_real = floor_real - 1.0_wp
  end function floor_real

  !> The names the script tests with Exists, or '(none)'.
  function tested_list(p) result(t)
    type(parser_t), intent(in) :: p
    character(len=:), allocatable :: t
    t = p%tested
    if (len(t) == 0) t = '(none)'
  end function tested_list

  !> The deck name nearest to the script's names, as " (did you mean 'x'?)".
  function nearest_name(p, name) result(hint)
    type(parser_t), intent(in) :: p
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: hint
    integer :: a, z, d, best
    hint = ''
    best = 3
    a = 1
    do while (a <= len(p%tested))
      z = index(p%tested(a:)//',', ',')
      d = edit_distance(trim(adjustl(p%tested(a:a + z - 2))), name)
      if (d < best) then
        best = d
        hint = " (did you mean '"//trim(adjustl(p%tested(a:a + z - 2)))//"'?)"
      end if
      a = a + z
    end do
  end function nearest_name

  ! ------------------------------------------------------------------ the model

  subroutine add_op(m, kind, tag, line, sub, ints, reals)
    type(geo_model_t), intent(inout) :: m
    integer, intent(in) :: kind, tag, line, sub, ints(:)
    real(wp), intent(in) :: reals(:)
    if (.not. allocated(m%kind)) then
      allocate(m%kind(32), m%tag(32), m%line(32), m%sub(32), m%i0(32), m%ni(32), &
        m%r0(32), m%nr(32), m%ints(64), m%reals(64))
    end if
    if (m%nops == size(m%kind)) then
      call grow_int(m%kind)
      call grow_int(m%tag)
      call grow_int(m%line)
      call grow_int(m%sub)
      call grow_int(m%i0)
      call grow_int(m%ni)
      call grow_int(m%r0)
      call grow_int(m%nr)
    end if
    do while (m%nints + size(ints) > size(m%ints))
      call grow_int(m%ints)
    end do
    do while (m%nreals + size(reals) > size(m%reals))
      call grow_real(m%reals)
    end do
    m%nops = m%nops + 1
    m%kind(m%nops) = kind
    m%tag(m%nops) = tag
    m%line(m%nops) = line
    m%sub(m%nops) = sub
    m%i0(m%nops) = m%nints + 1
    m%ni(m%nops) = size(ints)
    m%r0(m%nops) = m%nreals + 1
    m%nr(m%nops) = size(reals)
    m%ints(m%nints + 1:m%nints + size(ints)) = ints
    m%reals(m%nreals + 1:m%nreals + size(reals)) = reals
    m%nints = m%nints + size(ints)
    m%nreals = m%nreals + size(reals)
  end subroutine add_op

  !> Arrays allocated even for an empty model.
  subroutine finish_model(m)
    type(geo_model_t), intent(inout) :: m
    if (.not. allocated(m%kind)) then
      allocate(m%kind(0), m%tag(0), m%line(0), m%sub(0), m%i0(0), m%ni(0), m%r0(0), &
        m%nr(0), m%ints(0), m%reals(0))
    end if
  end subroutine finish_model

  subroutine move_alloc_model(a, b)
    type(geo_model_t), intent(inout) :: a
    type(geo_model_t), intent(out) :: b
    b%nops = a%nops
    b%nints = a%nints
    b%nreals = a%nreals
    b%nsurfaces = a%nsurfaces
    call move_alloc(a%kind, b%kind)
    call move_alloc(a%tag, b%tag)
    call move_alloc(a%line, b%line)
    call move_alloc(a%sub, b%sub)
    call move_alloc(a%i0, b%i0)
    call move_alloc(a%ni, b%ni)
    call move_alloc(a%r0, b%r0)
    call move_alloc(a%nr, b%nr)
    call move_alloc(a%ints, b%ints)
    call move_alloc(a%reals, b%reals)
  end subroutine move_alloc_model

  ! ------------------------------------------------------------------ the mesh's size

  !> A count that the triangles gmsh makes of the model's plane surfaces cannot go much
  !! below: the sum over each surface of area / h_hi^2, where h_hi bounds the mesh size
  !! from above at each point of the surface. gmsh's size at a point is the smallest of
  !! the sizes of the points interpolated over the boundary and extended inside (with
  !! Mesh.MeshSizeFromPoints and Mesh.MeshSizeExtendFromBoundary), of the background field
  !! and of the curvature, clamped to [Mesh.MeshSizeMin, Mesh.MeshSizeMax] and scaled by
  !! Mesh.MeshSizeFactor; any one source gives an upper bound. The points' bound is the
  !! largest size at the surface's curve ends; the field's is evaluated on a grid over the
  !! surface, cell by cell, at the largest distance a cell's points can have. A triangle
  !! whose edges are at most 1.5 h has an area below 0.98 h^2, so a mesh of size h holds
  !! at least about area/h^2 of them (gmsh's hold about 2.3 area/h^2: an equilateral
  !! triangle of side h has area 0.433 h^2). Fields the bound does not model (Cylinder,
  !! Constant, Restrict, a decreasing Threshold) give no bound, so they never make the
  !! count too high. Surfaces that are not plane (Surface) are not counted. The work is
  !! bounded whatever the script: about 2^18 grid cells over all surfaces, fewer on a
  !! surface with a long boundary, and at most 500 sample points a Distance field.
  real(wp) function geo_min_triangles(m) result(total)
    type(geo_model_t), intent(in) :: m
    type(est_t) :: c
    integer :: k, nfields, nsurf, nside
    type(ieee_status_type) :: fp
    ! sizes from a script may be tiny or huge: an overflow is a huge count, not a trap
    call ieee_get_status(fp)
    call ieee_set_halting_mode(ieee_all, .false.)
    total = 0.0_wp
    nfields = 0
    nsurf = 0
    do k = 1, m%nops
      select case (m%kind(k))
      case (op_point)
        call c%points%put(m%tag(k), k)
      case (op_line, op_circle, op_ellipse, op_spline, op_bspline)
        call c%curves%put(m%tag(k), k)
      case (op_curve_loop)
        call c%loops%put(m%tag(k), k)
      case (op_field)
        nfields = nfields + 1
        call c%fields%put(m%tag(k), nfields)
      case (op_background)
        c%background = m%tag(k)
      case (op_plane_surface)
        nsurf = nsurf + 1
      case (op_mesh_option)
        select case (geo_mesh_option(m%sub(k)))
        case ('MeshSizeMin')
          c%size_min = m%reals(m%r0(k))
        case ('MeshSizeMax')
          c%size_max = m%reals(m%r0(k))
        case ('MeshSizeFactor')
          c%factor = m%reals(m%r0(k))
        case ('MeshSizeFromPoints')
          c%from_points = m%reals(m%r0(k))
        case ('MeshSizeExtendFromBoundary')
          c%extend = m%reals(m%r0(k))
        end select
      end select
    end do
    if (nsurf == 0) then
      call ieee_set_status(fp)
      return
    end if
    allocate(c%est(max(nfields, 1)))
    call read_fields(m, c, nfields)
    nside = max(8, int(512.0_wp/sqrt(real(nsurf, wp))))
    do k = 1, m%nops
      if (m%kind(k) == op_plane_surface) total = total + surface_count(m, c, k, nside)
    end do
    if (.not. ieee_is_finite(total)) total = huge(1.0_wp)
    call ieee_set_status(fp)
  end function geo_min_triangles

  integer function field_index(c, tag)
    type(est_t), intent(in) :: c
    integer, intent(in) :: tag
    logical :: f
    field_index = c%fields%get(tag, f)
    if (.not. f) field_index = 0
  end function field_index

  !> What the bound needs of each field, from its options as the script last set them.
  subroutine read_fields(m, c, nfields)
    type(geo_model_t), intent(in) :: m
    type(est_t), intent(inout) :: c
    integer, intent(in) :: nfields
    integer, parameter :: max_samples = 500
    integer :: j, f, cv, i, n, k, slot
    real(wp), allocatable :: poly(:, :)
    logical :: found
    do k = 1, m%nops
      select case (m%kind(k))
      case (op_field)
        f = c%fields%get(m%tag(k), found)
        c%est(f)%kind = m%sub(k)
        allocate(c%est(f)%x(3, 16))
      case (op_field_number, op_field_list)
        f = field_index(c, m%tag(k))
        slot = 0
        select case (geo_field_option(m%sub(k)))
        case ('SizeMin', 'VIn')
          slot = 1
        case ('SizeMax', 'VOut')
          slot = 2
        case ('DistMin', 'Radius')
          slot = 3
        case ('DistMax', 'Thickness')
          slot = 4
        case ('InField')
          slot = 5
        case ('Sigmoid')
          slot = 6
        case ('StopAtDistMax')
          slot = 7
        case ('XMin', 'XCenter')
          slot = 8
        case ('YMin', 'YCenter')
          slot = 9
        case ('ZMin', 'ZCenter')
          slot = 10
        case ('XMax')
          slot = 11
        case ('YMax')
          slot = 12
        case ('ZMax')
          slot = 13
        case ('Sampling')
          slot = 14
        case ('FieldsList')
          c%est(f)%children = [(field_index(c, int(m%reals(j))), j = m%r0(k), &
            m%r0(k) + m%nr(k) - 1)]
        case ('PointsList')
          do j = m%r0(k), m%r0(k) + m%nr(k) - 1
            i = c%points%get(int(m%reals(j)), found)
            if (found) call add_sample(c%est(f), m%reals(m%r0(i):m%r0(i) + 2))
          end do
        end select
        if (slot > 0) then
          c%est(f)%par(slot) = m%reals(m%r0(k))
          c%est(f)%set(slot) = .true.
        end if
      end select
    end do
    ! the curves of Distance fields, sampled as gmsh samples them (Sampling, default 20)
    do k = 1, m%nops
      if (m%kind(k) /= op_field_list) cycle
      if (geo_field_option(m%sub(k)) /= 'CurvesList') cycle
      f = field_index(c, m%tag(k))
      n = 20
      if (c%est(f)%set(14)) n = max(2, int(c%est(f)%par(14)))
      do j = m%r0(k), m%r0(k) + m%nr(k) - 1
        cv = c%curves%get(int(abs(m%reals(j))), found)
        if (.not. found) cycle
        call curve_polyline(m, c, cv, min(n, 1000), poly)
        do i = 1, size(poly, 2)
          call add_sample(c%est(f), poly(:, i))
        end do
      end do
    end do
    ! fewer points only lengthen the distances, so the bound stays a bound
    do f = 1, nfields
      if (c%est(f)%ns > max_samples) then
        n = (c%est(f)%ns + max_samples - 1)/max_samples
        c%est(f)%x = c%est(f)%x(:, 1:c%est(f)%ns:n)
        c%est(f)%ns = size(c%est(f)%x, 2)
      end if
    end do
  end subroutine read_fields

  !> The points of curve call cv: its ends and, for arcs and splines, points between
  !! (nseg segments for arcs).
  subroutine curve_polyline(m, c, cv, nseg, poly)
    type(geo_model_t), intent(in) :: m
    type(est_t), intent(in) :: c
    integer, intent(in) :: cv, nseg
    real(wp), allocatable, intent(out) :: poly(:, :)
    real(wp) :: s(3), o(3), e(3), u(3), w(3), v(3), r0, r1, th, t
    integer :: j, a
    a = m%i0(cv)
    select case (m%kind(cv))
    case (op_line, op_spline, op_bspline)
      allocate(poly(3, m%ni(cv)))
      do j = 1, m%ni(cv)
        poly(:, j) = point_xyz(m, c, m%ints(a + j - 1))
      end do
    case default
      ! an arc about its centre from start to end, the radius going from |s - o| to
      ! |e - o| (a circle's are equal; an ellipse's arc is near this)
      s = point_xyz(m, c, m%ints(a))
      o = point_xyz(m, c, m%ints(a + 1))
      e = point_xyz(m, c, m%ints(a + m%ni(cv) - 1))
      r0 = norm2(s - o)
      r1 = norm2(e - o)
      w = cross(s - o, e - o)
      if (r0 == 0.0_wp .or. r1 == 0.0_wp .or. norm2(w) == 0.0_wp) then
        allocate(poly(3, 2))
        poly(:, 1) = s
        poly(:, 2) = e
        return
      end if
      allocate(poly(3, nseg + 1))
      u = (s - o)/r0
      w = w/norm2(w)
      v = cross(w, u)
      th = atan2(dot_product(e - o, v), dot_product(e - o, u))
      do j = 0, nseg
        t = real(j, wp)/real(nseg, wp)
        poly(:, j + 1) = o + ((1.0_wp - t)*r0 + t*r1)*(cos(t*th)*u + sin(t*th)*v)
      end do
    end select
  end subroutine curve_polyline

  function point_xyz(m, c, tag) result(x)
    type(geo_model_t), intent(in) :: m
    type(est_t), intent(in) :: c
    integer, intent(in) :: tag
    real(wp) :: x(3)
    integer :: i
    logical :: f
    i = c%points%get(tag, f)
    x = 0.0_wp
    if (f) x = m%reals(m%r0(i):m%r0(i) + 2)
  end function point_xyz

  !> The lower count of one plane surface (call k), on a grid of about nside x nside.
  real(wp) function surface_count(m, c, k, nside) result(cnt)
    type(geo_model_t), intent(in) :: m
    type(est_t), intent(in) :: c
    integer, intent(in) :: k, nside
    real(wp), allocatable :: poly(:, :), loopxy(:, :), seg(:, :)
    integer, allocatable :: lstart(:)
    real(wp) :: nrm(3), lo(2), hi(2), dx, dy, cell, c2(2), c3(3), r, h, hpts, scale
    integer :: j, l, i, ax(2), drop, nl, ix, iy, cv, np, ns, narc, ncurves, e, ip
    logical :: found, has_zero
    cnt = 0.0_wp
    hpts = 0.0_wp
    has_zero = .false.
    ! arcs in fewer segments on a surface with many curves
    ncurves = 0
    do j = m%i0(k), m%i0(k) + m%ni(k) - 1
      l = c%loops%get(m%ints(j), found)
      if (found) ncurves = ncurves + m%ni(l)
    end do
    narc = max(2, min(32, 20000/max(1, ncurves)))
    ! the loops' polylines, one after another (lstart: where each starts)
    allocate(poly(3, 256), lstart(m%ni(k) + 1))
    np = 0
    nl = 0
    do j = m%i0(k), m%i0(k) + m%ni(k) - 1
      l = c%loops%get(m%ints(j), found)
      if (.not. found) return
      nl = nl + 1
      lstart(nl) = np + 1
      do i = m%i0(l), m%i0(l) + m%ni(l) - 1
        cv = c%curves%get(abs(m%ints(i)), found)
        if (.not. found) return
        call curve_polyline(m, c, cv, narc, seg)
        if (m%ints(i) < 0) seg = seg(:, size(seg, 2):1:-1)
        do while (np + size(seg, 2) > size(poly, 2))
          poly = reshape(poly, [3, 2*size(poly, 2)], pad=[0.0_wp])
        end do
        poly(:, np + 1:np + size(seg, 2)) = seg
        np = np + size(seg, 2)
        ! the largest mesh size at the curve's ends (a point without one, 0, takes
        ! gmsh's largest: no bound)
        do e = m%i0(cv), m%i0(cv) + m%ni(cv) - 1, max(1, m%ni(cv) - 1)
          ip = c%points%get(m%ints(e), found)
          if (.not. found) cycle
          if (m%reals(m%r0(ip) + 3) <= 0.0_wp) has_zero = .true.
          hpts = max(hpts, m%reals(m%r0(ip) + 3))
        end do
      end do
    end do
    lstart(nl + 1) = np + 1
    if (np < 3) return
    ! Newell's normal of the outer loop: the plane, and the axis it is projected along
    nrm = 0.0_wp
    do i = lstart(1), lstart(2) - 1
      j = merge(lstart(1), i + 1, i == lstart(2) - 1)
      nrm = nrm + cross(poly(:, i), poly(:, j))
    end do
    if (norm2(nrm) == 0.0_wp) return
    drop = maxloc(abs(nrm), 1)
    ax = pack([1, 2, 3], [1, 2, 3] /= drop)
    scale = norm2(nrm)/abs(nrm(drop))   ! area in the plane per projected area
    loopxy = poly(ax, 1:np)
    lo = minval(loopxy, 2)
    hi = maxval(loopxy, 2)
    ! cells x boundary points at most about 2e8
    ns = max(4, min(nside, int(sqrt(2.0e8_wp/real(np, wp)))))
    dx = (hi(1) - lo(1))/ns
    dy = (hi(2) - lo(2))/ns
    if (dx <= 0.0_wp .or. dy <= 0.0_wp) return
    if (c%from_points == 0.0_wp .or. c%extend == 0.0_wp .or. has_zero) hpts = huge(1.0_wp)
    cell = dx*dy*scale
    r = 0.5_wp*sqrt(dx*dx + dy*dy)*scale
    do iy = 1, ns
      do ix = 1, ns
        c2 = [lo(1) + (ix - 0.5_wp)*dx, lo(2) + (iy - 0.5_wp)*dy]
        if (.not. inside(loopxy, lstart(1:nl + 1), c2)) cycle
        ! the cell's centre in the surface's plane
        c3(ax) = c2
        c3(drop) = (dot_product(nrm, poly(:, lstart(1))) - nrm(ax(1))*c2(1) - &
          nrm(ax(2))*c2(2))/nrm(drop)
        h = hpts
        if (c%background /= 0) h = min(h, field_hi(c, field_index(c, c%background), c3, r, 0))
        h = min(max(h, c%size_min), c%size_max)*c%factor
        if (h < 1.0e21_wp) cnt = cnt + cell/(h*h)
      end do
    end do
  end function surface_count

  !> Whether q is inside the loops xy(:, lstart(l) : lstart(l + 1) - 1) (even-odd rule).
  pure logical function inside(xy, lstart, q)
    real(wp), intent(in) :: xy(:, :), q(2)
    integer, intent(in) :: lstart(:)
    integer :: a, b, ll
    inside = .false.
    do ll = 1, size(lstart) - 1
      do a = lstart(ll), lstart(ll + 1) - 1
        b = merge(lstart(ll), a + 1, a == lstart(ll + 1) - 1)
        if ((xy(2, a) > q(2)) .neqv. (xy(2, b) > q(2))) then
          if (q(1) < xy(1, a) + (q(2) - xy(2, a))*(xy(1, b) - xy(1, a))/ &
            (xy(2, b) - xy(2, a))) inside = .not. inside
        end if
      end do
    end do
  end function inside

  !> An upper bound of field f's value over the ball of radius r about x (huge when the
  !! field is not modelled or not fully set).
  recursive real(wp) function field_hi(c, f, x, r, depth) result(h)
    type(est_t), intent(in) :: c
    integer, intent(in) :: f, depth
    real(wp), intent(in) :: x(3), r
    real(wp) :: smin, smax, dmin, dmax, d, t
    integer :: j
    h = huge(1.0_wp)
    if (f == 0 .or. depth > 50) return
    associate (e => c%est(f))
      if (e%kind == 0) return
      select case (trim(field_types(e%kind)))
      case ('Distance')
        if (e%ns == 0) return
        d = huge(1.0_wp)
        do j = 1, e%ns
          d = min(d, norm2(x - e%x(:, j)))
        end do
        h = d + r
      case ('Threshold')
        if (.not. all(e%set(1:5))) return
        smin = e%par(1)
        smax = e%par(2)
        dmin = e%par(3)
        dmax = e%par(4)
        if (smax < smin) return
        d = field_hi(c, field_index(c, int(e%par(5))), x, r, depth + 1)
        if (e%set(7)) then
          if (e%par(7) /= 0.0_wp .and. d >= dmax) return
        end if
        if (d <= dmin) then
          h = smin
        else if (d >= dmax .or. dmax <= dmin) then
          h = smax
        else if (e%set(6) .and. e%par(6) /= 0.0_wp) then
          h = smax
        else
          h = smin + (smax - smin)*(d - dmin)/(dmax - dmin)
        end if
      case ('Min')
        if (.not. allocated(e%children)) return
        do j = 1, size(e%children)
          h = min(h, field_hi(c, e%children(j), x, r, depth + 1))
        end do
      case ('Max')
        if (.not. allocated(e%children)) return
        if (size(e%children) == 0) return
        h = 0.0_wp
        do j = 1, size(e%children)
          h = max(h, field_hi(c, e%children(j), x, r, depth + 1))
        end do
      case ('Box')
        if (.not. (all(e%set(1:2)) .and. all(e%set(8:13)))) return
        t = merge(e%par(4), 0.0_wp, e%set(4))
        if (all(x - r >= e%par(8:10)) .and. all(x + r <= e%par(11:13))) then
          h = e%par(1)
        else if (any(x + r < e%par(8:10) - t) .or. any(x - r > e%par(11:13) + t)) then
          h = e%par(2)
        else
          h = max(e%par(1), e%par(2))
        end if
      case ('Ball')
        if (.not. (all(e%set(1:3)) .and. all(e%set(8:10)))) return
        t = merge(e%par(4), 0.0_wp, e%set(4))
        d = norm2(x - e%par(8:10))
        if (d + r <= e%par(3)) then
          h = e%par(1)
        else if (d - r > e%par(3) + t) then
          h = e%par(2)
        else
          h = max(e%par(1), e%par(2))
        end if
      end select
    end associate
  end function field_hi

  subroutine add_sample(e, x)
    type(est_field_t), intent(inout) :: e
    real(wp), intent(in) :: x(3)
    if (e%ns == size(e%x, 2)) e%x = reshape(e%x, [3, 2*size(e%x, 2)], pad=[0.0_wp])
    e%ns = e%ns + 1
    e%x(:, e%ns) = x
  end subroutine add_sample
end module geo_script_m
