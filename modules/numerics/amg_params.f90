!> Settings of the BoomerAMG preconditioner, with defaults for 3D Q1
!> elasticity (displacement dofs interleaved node by node, 3 per node).
!>
!> Choices are names (as in the deck); the hypre ids are looked up here, in
!> one place, from the comments of HYPRE_parcsr_ls.h of hypre 2.26:
!>   coarsen_type    : cljp 0, ruge-stueben 3 (with the boundary third pass),
!>                     falgout 6, pmis 8, hmis 10
!>   interp_type     : classical 0, direct 3, multipass 4, ext+i 6, standard 8,
!>                     ff1 13, ext 14, ext-mm 16, ext+i-mm 17, ext+e-mm 18
!>   agg_interp_type : 2s-ext+i 1, 2s-standard 2, 2s-ext 3, multipass 4,
!>                     2s-ext-mm 5, 2s-ext+i-mm 6, 2s-ext+e-mm 7
!>   relax_type      : down/up smoother of the V-cycle
!>                     jacobi 0/0, hybrid-gs 3/4 (forward down, backward up),
!>                     hybrid-sgs 6/6, l1-sgs 8/8, l1-gs 13/14, chebyshev 16/16,
!>                     l1-jacobi 18/18; the coarsest level is always solved
!>                     by Gaussian elimination (9). Every pair is symmetric, so
!>                     the V-cycle is a symmetric preconditioner fit for PCG.
!>   relax_order     : lexicographic 0 (rows in their order), cf 1 (C points,
!>                     then F points: hypre's own default)
!>   cycle_type      : v 1, w 2 (hypre's cycle types; both symmetric, fit for PCG)
!>   nodal           : 0 unknown approach (coarsen each function alone);
!>                     1 Frobenius, 2 sum of |a|, 3 largest entry, 4 row sum,
!>                     6 sum of entries of each nodal block
!>
!> Defaults and why:
!>   num_functions 3, nodal 0  : the "unknown approach" for elasticity; each
!>                               displacement component is coarsened on its own.
!>   hmis + ext+i, one aggressive level (multipass): hypre's recommended
!>                               low-complexity 3D set-up.
!>   p_max_elmts 6             : on the benchmark cube (clamped x = 0, shear
!>                               traction on x = 1, nu = 0.25, CG to 1e-8, 1 rank)
!>                               at 15k, 108k, 824k unknowns: 20, 21, 23
!>                               iterations (growth 1.15x) and 13.9 s to solve
!>                               at 824k, against 20, 22, 27 (1.35x) and 17.0 s
!>                               with 4. 2s-ext+i on the aggressive level gave 21
!>                               at 824k but made CG stagnate on a 4^3 mesh with
!>                               Dirichlet rows, so it is not the default.
!>   strong_threshold 0.5      : the hypre manual suggests 0.5-0.6 for 3D Laplace
!>                               and "a large strength threshold, such as 0.9"
!>                               for elasticity. Measured on Q1 elasticity cubes
!>                               (clamped base, nu = 0.3, p_max_elmts 4, the
!>                               other defaults, PCG to 1e-8, 1 rank) of 15k, 108k,
!>                               353k and 824k unknowns: 0.5 took 21, 22, 24, 25
!>                               iterations, 0.8 took 21, 23, 25, 27 with grid
!>                               complexity 1.45 instead of 1.33 and ~30% more
!>                               solve time, 0.25 took 25, 29, 31.
!>   l1-gs, 1 sweep            : hypre's default smoother, robust in parallel,
!>                               run by geoblock's cycle (cycle_code
!>                               'geoblock', amg_cycle.c): hypre 2.26's
!>                               backward sweep reads each row upwards while
!>                               it walks the rows down, against the
!>                               hardware prefetch, and took 5x its forward
!>                               sweep's time; ours reads that sweep
!>                               downwards. With it l1-gs is the default of
!>                               every physics again (2026-12-04, 2 ranks,
!>                               single runs): the clamped cube at n = 64,
!>                               CG, 26 iterations and a solve of 4.4 s
!>                               against Chebyshev's 25 and 5.8 s (1 rank:
!>                               23 and 5.3-5.7 s against 23 and 11.1 s);
!>                               Mandel at the seed's size (gamma 0.15, 1,
!>                               100) 31, 29, 21 FGMRES iterations against
!>                               Chebyshev's 29, 26, 19, set-up + solve
!>                               1.7-2.1, 1.8, 1.5 s against 2.3-3.1, 2.2,
!>                               1.7-2.1 s. Chebyshev (2026-12-02 to -04
!>                               elasticity's and Biot's default) streams
!>                               at 65-76 % of the triad but costs hypre's
!>                               eigenvalue estimates in every set-up.
!>   precision single          : geoblock's cycle reads each level's values
!>                               in single precision (amg_cycle.c; 8 bytes
!>                               an entry with its column index instead of
!>                               12, summed in double against double
!>                               vectors), every level converted in place
!>                               in hypre's arrays (the finest level's
!>                               doubles, the IJ matrix, come back with
!>                               the next values written into it). The
!>                               same counts on every case
!>                               measured (the rounding moves M^-1 x by
!>                               3e-8 of its largest entry), less solve
!>                               time (2 ranks, 2026-12-04, a busy machine,
!>                               pairs run one after the other): the cube
!>                               at n = 64, CG, 26 iterations, 3.2 s
!>                               against 4.0-4.2 s (1 rank 4.3-4.4 s
!>                               against 5.3-5.6 s); Mandel at the seed's
!>                               size, gamma 1, 29 FGMRES iterations, 1.04-
!>                               1.06 s against 1.23-1.27 s; the nine
!>                               fractures on 34 x 34 x 69 cells, the same
!>                               Newton counts and end state, FGMRES 1,599
!>                               against 1,593, 73 and 85 s against 103
!>                               and 107 s; at the seed's size 229 s
!>                               against 279 s (the run 492 s against
!>                               535 s). Costs: a pass over the
!>                               hierarchy per set-up. A copy of the
!>                               finest level kept between set-ups (until
!>                               2026-12-05) cost +13 % peak on the cube,
!>                               +8 % on the seed's nine fractures and
!>                               390 MB a rank on HI24L. A first version
!>                               that copied every level into fresh memory
!>                               cost 0.8 s of page faults and copying per
!>                               set-up of S** at the seed's size (55 of
!>                               them), more than its solve saved there.
!>   relax_order lexicographic : the Gauss-Seidel sweeps run through the rows
!>                               once, in their order, rather than hypre's
!>                               C-then-F order, which walks every level's
!>                               rows twice (the smoother was 49 % of the
!>                               seed's nine-fracture opening step, perf on
!>                               rank 0). The same counts, less time
!>                               (2 ranks, 2026-12-02): CG on the 824k cube
!>                               26 iterations either way, solve 7.2-7.7 s
!>                               against 9.0-10.0 s (0.78x, two pairs); the
!>                               nine fractures' step 5 restarted (4 Newton
!>                               iterations, 142-143 FGMRES), the solve
!>                               53-64 s against 74-81 s (0.77x, three
!>                               pairs); the whole seed nine-fracture run
!>                               0.290 s an FGMRES iteration against
!>                               0.365 s (0.79x), 925 s against 1,358 s.
!>   V-cycle                   : the W-cycle visits the coarse levels 2^l times
!>                               and keeps the counts flat where the V-cycle's
!>                               grow: CG on the benchmark cube (2 ranks, the
!>                               other defaults) at 15k, 108k, 824k unknowns
!>                               took 19, 19, 19 iterations against 21, 22, 26,
!>                               but 11.2 s to solve at 824k against 6.9 s (2.2x
!>                               per iteration; 2026-11-27). hypre's manual
!>                               advises against it at scale (the coarse levels'
!>                               communication), so it is an option.
!>   no interpolation vectors  : the six rigid-body modes in the interpolation
!>                               (interp_vec_variant 1 or 2, hypre's GM, with
!>                               nodal coarsening) did not beat the unknown
!>                               approach here (2 ranks, 2026-11-26): CG on
!>                               the 40^3 cube 22 iterations against 24 (GM1,
!>                               GM2; nodal = 4 alone: 32); the reduced
!>                               nine-fracture case's u-t-p systems 27/16/65/36
!>                               against 33/19/72/42 (GM2) and 32/19/72/41
!>                               (GM1); the contact block at n = 40, 34-38
!>                               against 35-43.
!>   slab_threshold 0.8        : the strength threshold, at least, of the AMG of
!>                               the displacement block (K, S*) on a slab with
!>                               flat cells (slab_geometry.f90 finds it; the
!>                               physics apply it with for_slab()). On flat
!>                               cells the through-thickness coupling weighs
!>                               a node's neighbours on the opposite face like
!>                               a mass matrix (4:2:1 per cell), so the node
!>                               across the thickness is the strongest, and
!>                               at the mesh's boundaries (box faces, fault
!>                               faces) its neighbours beside it weigh
!>                               exactly 1/2 of it: at 0.5 they tie, to the
!>                               round-off, and the strong ones pair nodes
!>                               diagonally. Measured (CG to 1e-8, 1 rank):
!>                               the 59 m plane-strain slab one cell thick
!>                               (186k unknowns, 8.7 mm cells graded to
!>                               1:671) failed in 1,000 iterations at 0.5
!>                               (and 0.45) and took 19 at 0.51 and 0.55, 20
!>                               at 0.6, 22 at 0.7, 30 at 0.8, 33 at 0.9; two
!>                               and four cells thick failed too at 0.5 (21
!>                               at 0.6 for two). S* of contact adds the
!>                               fault's faces, mass-weighted the same way
!>                               across the fault: FGMRES (reordered, per
!>                               Newton iteration, the fault slipping) did
!>                               not converge at 0.55 on that slab, 58/58/34
!>                               at 0.6, 45/45/21 at 0.7, 46/47/19 at 0.8,
!>                               49/51/21 at 0.9; on a 10k-unknown slab
!>                               (tests/verification/slab_amg.sh, 2 ranks)
!>                               558/359/100 at 0.6, 60/58/26 at 0.7,
!>                               48/46/20 at 0.8: 0.8 keeps a margin from
!>                               that cliff. On cubes 0.55 already moved one
!>                               count (22 -> 23, 108k, 2 ranks), hence a
!>                               slab's setting rather than a new default.
module amg_params
  use kinds, only: rp, name_len
  use error_status, only: error_status_t
  implicit none
  private

  public :: amg_params_t, amg_line_len

  !> Length of the lines returned by to_lines().
  integer, parameter :: amg_line_len = 96

  !> The BoomerAMG settings; see the module header for the names and ids.
  type :: amg_params_t
    integer :: num_functions = 3                      !< unknowns per node (systems AMG)
    integer :: nodal = 0                              !< 0 unknown approach; 1-4, 6 nodal norms
    character(len=name_len) :: coarsen_type = 'hmis'
    character(len=name_len) :: interp_type = 'ext+i'
    integer :: p_max_elmts = 6                        !< interpolation entries per row (0: all)
    real(rp) :: trunc_factor = 0.0_rp                 !< interpolation truncation factor
    integer :: agg_num_levels = 1                     !< levels of aggressive coarsening
    character(len=name_len) :: agg_interp_type = 'multipass'
    integer :: agg_p_max_elmts = 0                    !< entries per row, aggressive levels (0: all)
    integer :: num_paths = 1                          !< paths of aggressive coarsening
    real(rp) :: strong_threshold = 0.5_rp             !< strength of connection
    real(rp) :: max_row_sum = 0.9_rp                  !< weakens diagonally dominant rows (1: off)
    integer :: max_levels = 25
    integer :: max_coarse_size = 9                    !< rows of the coarsest level
    character(len=name_len) :: relax_type = 'l1-gs'
    character(len=name_len) :: relax_order = 'lexicographic'  !< 'lexicographic' or 'cf'
    integer :: num_sweeps = 1                         !< smoothing sweeps down and up
    character(len=name_len) :: cycle_type = 'v'       !< 'v' or 'w'
    real(rp) :: relax_wt = 1.0_rp                     !< weight of Jacobi / SOR smoothers
    integer :: print_level = 0                        !< hypre's own output: 0 none .. 3
    !> interpolation of the near-null space the caller gives (rigid-body
    !> modes), hypre's variant: 0 none, 1 and 2 GM, 3 LN; needs nodal > 0
    integer :: interp_vec_variant = 0
    integer :: interp_vec_qmax = 4                    !< entries per row of the added columns (0: all)
    !> strength threshold, at least, of the displacement block's AMG on a
    !> slab with flat cells (for_slab); 0: as strong_threshold
    real(rp) :: slab_threshold = 0.8_rp
    !> the code that runs the cycle: 'geoblock' (amg_cycle.c over hypre's
    !> hierarchy, for l1-gs V-cycles in lexicographic order with unit
    !> weights; hypre's own cycle for every other setting) or 'hypre'
    character(len=name_len) :: cycle_code = 'geoblock'
    !> the level values in geoblock's cycle: 'double' or 'single' (float
    !> copies, 8 bytes an entry with its column instead of 12; amg_cycle.c)
    character(len=name_len) :: precision = 'single'
  contains
    procedure :: validate
    procedure :: to_lines
    procedure :: coarsen_id
    procedure :: interp_id
    procedure :: agg_interp_id
    procedure :: relax_ids
    procedure :: relax_order_id
    procedure :: cycle_id
    procedure :: scalar
    procedure :: for_slab
  end type amg_params_t

  character(len=*), parameter :: coarsen_names = 'cljp, ruge-stueben, falgout, pmis, hmis'
  character(len=*), parameter :: interp_names = &
    'classical, direct, multipass, ext+i, standard, ff1, ext, ext-mm, ext+i-mm, ext+e-mm'
  character(len=*), parameter :: agg_interp_names = &
    '2s-ext+i, 2s-standard, 2s-ext, multipass, 2s-ext-mm, 2s-ext+i-mm, 2s-ext+e-mm'
  character(len=*), parameter :: cycle_names = 'v, w'
  character(len=*), parameter :: order_names = 'lexicographic, cf'
  character(len=*), parameter :: relax_names = &
    'jacobi, hybrid-gs, hybrid-sgs, l1-sgs, l1-gs, chebyshev, l1-jacobi'

contains

  !> The same settings for a scalar operator (one unknown per row: Schur
  !> complements, pressure Laplacians): num_functions 1, a strength
  !> threshold of 0.25, and neither nodal coarsening nor interpolation
  !> vectors (a scalar operator has no node systems and no rigid-body modes;
  !> kept from an elastic &amg, they made the copy invalid for hypre).
  type(amg_params_t) function scalar(self) result(a)
    class(amg_params_t), intent(in) :: self
    a = self
    a%num_functions = 1
    a%strong_threshold = 0.25_rp
    a%nodal = 0
    a%interp_vec_variant = 0
  end function scalar

  !> The settings for the displacement block (K, S*) on a slab with flat
  !> cells (slab_geometry.f90): strong_threshold raised to slab_threshold
  !> (see the module header for why).
  type(amg_params_t) function for_slab(self) result(a)
    class(amg_params_t), intent(in) :: self
    a = self
    a%strong_threshold = max(self%strong_threshold, self%slab_threshold)
  end function for_slab

  !> Range-check every field; the first bad one is reported in status by
  !> name, value and accepted range. Not collective.
  subroutine validate(self, status)
    class(amg_params_t), intent(in) :: self
    type(error_status_t), intent(inout) :: status
    integer :: down, up

    if (self%num_functions < 1 .or. self%num_functions > 64) then
      call bad_int('num_functions', self%num_functions, 'an integer in 1..64')
    else if (all(self%nodal /= [0, 1, 2, 3, 4, 6])) then
      call bad_int('nodal', self%nodal, 'one of 0 (unknown approach), 1, 2, 3, 4, 6 (nodal norms)')
    else if (self%nodal > 0 .and. self%num_functions == 1) then
      call bad_int('nodal', self%nodal, '0 when num_functions = 1 (nodal coarsening needs systems)')
    else if (self%interp_vec_variant < 0 .or. self%interp_vec_variant > 3) then
      call bad_int('interp_vec_variant', self%interp_vec_variant, 'one of 0 (none), 1, 2 (GM), 3 (LN)')
    else if (self%interp_vec_variant > 0 .and. self%nodal == 0) then
      call bad_int('interp_vec_variant', self%interp_vec_variant, '0 when nodal = 0 (the rigid-body modes need '// &
                   'nodal coarsening)')
    else if (self%interp_vec_qmax < 0 .or. self%interp_vec_qmax > 100) then
      call bad_int('interp_vec_qmax', self%interp_vec_qmax, 'an integer in 0..100 (0: no limit)')
    else if (self%coarsen_id() < 0) then
      call bad_name('coarsen_type', self%coarsen_type, coarsen_names)
    else if (self%interp_id() < 0) then
      call bad_name('interp_type', self%interp_type, interp_names)
    else if (self%p_max_elmts < 0 .or. self%p_max_elmts > 100) then
      call bad_int('p_max_elmts', self%p_max_elmts, 'an integer in 0..100 (0: no limit)')
    else if (.not. (self%trunc_factor >= 0.0_rp .and. self%trunc_factor < 1.0_rp)) then
      call bad_real('trunc_factor', self%trunc_factor, 'a real in [0, 1)')
    else if (self%max_levels < 1 .or. self%max_levels > 100) then
      call bad_int('max_levels', self%max_levels, 'an integer in 1..100')
    else if (self%agg_num_levels < 0 .or. self%agg_num_levels >= self%max_levels) then
      call bad_int('agg_num_levels', self%agg_num_levels, 'an integer in 0..max_levels-1')
    else if (self%agg_interp_id() < 0) then
      call bad_name('agg_interp_type', self%agg_interp_type, agg_interp_names)
    else if (self%agg_p_max_elmts < 0 .or. self%agg_p_max_elmts > 100) then
      call bad_int('agg_p_max_elmts', self%agg_p_max_elmts, 'an integer in 0..100 (0: no limit)')
    else if (self%num_paths < 1 .or. self%num_paths > 10) then
      call bad_int('num_paths', self%num_paths, 'an integer in 1..10')
    else if (.not. (self%strong_threshold > 0.0_rp .and. self%strong_threshold < 1.0_rp)) then
      call bad_real('strong_threshold', self%strong_threshold, 'a real in (0, 1)')
    else if (.not. (self%max_row_sum > 0.0_rp .and. self%max_row_sum <= 1.0_rp)) then
      call bad_real('max_row_sum', self%max_row_sum, 'a real in (0, 1] (1: no check)')
    else if (self%max_coarse_size < 1) then
      call bad_int('max_coarse_size', self%max_coarse_size, 'a positive integer')
    else if (.not. relax_known()) then
      call bad_name('relax_type', self%relax_type, relax_names)
    else if (self%cycle_id() < 0) then
      call bad_name('cycle_type', self%cycle_type, cycle_names)
    else if (self%relax_order_id() < 0) then
      call bad_name('relax_order', self%relax_order, order_names)
    else if (self%num_sweeps < 1 .or. self%num_sweeps > 20) then
      call bad_int('num_sweeps', self%num_sweeps, 'an integer in 1..20')
    else if (.not. (self%relax_wt > 0.0_rp .and. self%relax_wt < 2.0_rp)) then
      call bad_real('relax_wt', self%relax_wt, 'a real in (0, 2)')
    else if (self%print_level < 0 .or. self%print_level > 3) then
      call bad_int('print_level', self%print_level, 'an integer in 0..3')
    else if (lower(self%cycle_code) /= 'geoblock' .and. lower(self%cycle_code) /= 'hypre') then
      call bad_name('cycle_code', self%cycle_code, 'geoblock, hypre')
    else if (lower(self%precision) /= 'double' .and. lower(self%precision) /= 'single') then
      call bad_name('precision', self%precision, 'double, single')
    else if (.not. (self%slab_threshold >= 0.0_rp .and. self%slab_threshold < 1.0_rp)) then
      call bad_real('slab_threshold', self%slab_threshold, 'a real in [0, 1) (0: as strong_threshold)')
    end if

  contains

    logical function relax_known()
      call self%relax_ids(down, up)
      relax_known = down >= 0
    end function relax_known

    subroutine bad_int(field, value, accepted)
      character(len=*), intent(in) :: field, accepted
      integer, intent(in) :: value
      character(len=32) :: v
      write(v, '(i0)') value
      call status%set('amg_params: '//field//' = '//trim(v)//' is not valid; expected '//accepted)
    end subroutine bad_int

    subroutine bad_real(field, value, accepted)
      character(len=*), intent(in) :: field, accepted
      real(rp), intent(in) :: value
      call status%set('amg_params: '//field//' = '//real_text(value)//' is not valid; expected '// &
                      accepted)
    end subroutine bad_real

    subroutine bad_name(field, value, accepted)
      character(len=*), intent(in) :: field, value, accepted
      call status%set('amg_params: '//field//' = '''//trim(value)//''' is not valid; expected one of: '// &
                      accepted)
    end subroutine bad_name
  end subroutine validate

  !> "name = value" lines of every field, for the log echo.
  subroutine to_lines(self, lines)
    class(amg_params_t), intent(in) :: self
    character(len=amg_line_len), allocatable, intent(out) :: lines(:)
    allocate(lines(25))
    lines(1) = int_line('num_functions', self%num_functions)
    lines(2) = int_line('nodal', self%nodal)
    lines(3) = 'coarsen_type = '//trim(self%coarsen_type)
    lines(4) = 'interp_type = '//trim(self%interp_type)
    lines(5) = int_line('p_max_elmts', self%p_max_elmts)
    lines(6) = 'trunc_factor = '//real_text(self%trunc_factor)
    lines(7) = int_line('agg_num_levels', self%agg_num_levels)
    lines(8) = 'agg_interp_type = '//trim(self%agg_interp_type)
    lines(9) = int_line('agg_p_max_elmts', self%agg_p_max_elmts)
    lines(10) = int_line('num_paths', self%num_paths)
    lines(11) = 'strong_threshold = '//real_text(self%strong_threshold)
    lines(12) = 'max_row_sum = '//real_text(self%max_row_sum)
    lines(13) = int_line('max_levels', self%max_levels)
    lines(14) = int_line('max_coarse_size', self%max_coarse_size)
    lines(15) = 'relax_type = '//trim(self%relax_type)
    lines(16) = int_line('num_sweeps', self%num_sweeps)
    lines(17) = 'relax_wt = '//real_text(self%relax_wt)
    lines(18) = int_line('print_level', self%print_level)
    lines(19) = 'cycle_type = '//trim(self%cycle_type)
    lines(20) = int_line('interp_vec_variant', self%interp_vec_variant)
    lines(21) = int_line('interp_vec_qmax', self%interp_vec_qmax)
    lines(22) = 'slab_threshold = '//real_text(self%slab_threshold)
    lines(23) = 'relax_order = '//trim(self%relax_order)
    lines(24) = 'cycle_code = '//trim(self%cycle_code)
    lines(25) = 'precision = '//trim(self%precision)
  end subroutine to_lines

  !> hypre id of coarsen_type, or -1 when the name is unknown.
  integer function coarsen_id(self)
    class(amg_params_t), intent(in) :: self
    select case (lower(self%coarsen_type))
    case ('cljp');         coarsen_id = 0
    case ('ruge-stueben'); coarsen_id = 3
    case ('falgout');      coarsen_id = 6
    case ('pmis');         coarsen_id = 8
    case ('hmis');         coarsen_id = 10
    case default;          coarsen_id = -1
    end select
  end function coarsen_id

  !> hypre id of interp_type, or -1 when the name is unknown.
  integer function interp_id(self)
    class(amg_params_t), intent(in) :: self
    select case (lower(self%interp_type))
    case ('classical'); interp_id = 0
    case ('direct');    interp_id = 3
    case ('multipass'); interp_id = 4
    case ('ext+i');     interp_id = 6
    case ('standard');  interp_id = 8
    case ('ff1');       interp_id = 13
    case ('ext');       interp_id = 14
    case ('ext-mm');    interp_id = 16
    case ('ext+i-mm');  interp_id = 17
    case ('ext+e-mm');  interp_id = 18
    case default;       interp_id = -1
    end select
  end function interp_id

  !> hypre id of agg_interp_type, or -1 when the name is unknown.
  integer function agg_interp_id(self)
    class(amg_params_t), intent(in) :: self
    select case (lower(self%agg_interp_type))
    case ('2s-ext+i');    agg_interp_id = 1
    case ('2s-standard'); agg_interp_id = 2
    case ('2s-ext');      agg_interp_id = 3
    case ('multipass');   agg_interp_id = 4
    case ('2s-ext-mm');   agg_interp_id = 5
    case ('2s-ext+i-mm'); agg_interp_id = 6
    case ('2s-ext+e-mm'); agg_interp_id = 7
    case default;         agg_interp_id = -1
    end select
  end function agg_interp_id

  !> hypre id of cycle_type (1 V, 2 W), or -1 when the name is unknown.
  integer function cycle_id(self)
    class(amg_params_t), intent(in) :: self
    select case (lower(self%cycle_type))
    case ('v');    cycle_id = 1
    case ('w');    cycle_id = 2
    case default;  cycle_id = -1
    end select
  end function cycle_id

  !> hypre id of relax_order (0 lexicographic, 1 C/F), or -1 when the name is
  !> unknown.
  integer function relax_order_id(self)
    class(amg_params_t), intent(in) :: self
    select case (lower(self%relax_order))
    case ('lexicographic'); relax_order_id = 0
    case ('cf');            relax_order_id = 1
    case default;           relax_order_id = -1
    end select
  end function relax_order_id

  !> hypre ids of the down- and up-cycle smoothers of relax_type, or -1 and
  !> -1 when the name is unknown.
  subroutine relax_ids(self, down, up)
    class(amg_params_t), intent(in) :: self
    integer, intent(out) :: down, up
    select case (lower(self%relax_type))
    case ('jacobi');     down = 0;  up = 0
    case ('hybrid-gs');  down = 3;  up = 4
    case ('hybrid-sgs'); down = 6;  up = 6
    case ('l1-sgs');     down = 8;  up = 8
    case ('l1-gs');      down = 13; up = 14
    case ('chebyshev');  down = 16; up = 16
    case ('l1-jacobi');  down = 18; up = 18
    case default;        down = -1; up = -1
    end select
  end subroutine relax_ids

  ! ---- helpers ---------------------------------------------------------------

  !> Lower-case, left-adjusted, trimmed copy of a name.
  function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    integer :: i, c
    t = trim(adjustl(s))
    do i = 1, len(t)
      c = iachar(t(i:i))
      if (c >= iachar('A') .and. c <= iachar('Z')) t(i:i) = achar(c + 32)
    end do
  end function lower

  function int_line(name, value) result(line)
    character(len=*), intent(in) :: name
    integer, intent(in) :: value
    character(len=amg_line_len) :: line
    write(line, '(a,a,i0)') name, ' = ', value
  end function int_line

  function real_text(x) result(s)
    real(rp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    write(buf, '(g0.6)') x
    s = trim(adjustl(buf))
  end function real_text
end module amg_params
