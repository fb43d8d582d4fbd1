!> Deck group &amg: the BoomerAMG settings (optional; defaults suit 3D Q1
!> elasticity). Variables have the names of amg_params_t's fields; see
!> modules/numerics/amg_params.f90 for their meaning, ids and defaults:
!>   num_functions, nodal, coarsen_type, interp_type, p_max_elmts, trunc_factor,
!>   agg_num_levels, agg_interp_type, agg_p_max_elmts, num_paths,
!>   strong_threshold, max_row_sum, max_levels, max_coarse_size, relax_type,
!>   relax_order, num_sweeps, relax_wt, print_level, cycle_type,
!>   interp_vec_variant, interp_vec_qmax, slab_threshold, cycle_code, precision
!> slab_threshold (a real in [0, 1), default 0.8; 0: as strong_threshold): on
!> a slab with flat cells (a plane-strain mesh one or a few cells thick,
!> found from the mesh: src/discretization/slab_geometry.f90), the strength
!> threshold of the displacement block's BoomerAMG (K; S* of contact and
!> fracture flow) is at least this; the log says when it applies. Scalar
!> blocks keep their own. On such a slab S*'s BoomerAMG also takes at least
!> 3 smoothing sweeps (coupled_simulation.f90; a larger num_sweeps stays).
module amg_config
  use kinds, only: rp, name_len, msg_len
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t, line_len
  use amg_params, only: amg_params_t
  use param_group, only: param_group_t
  implicit none
  private

  public :: read_amg_config, describe_amg_config

contains

  !> Read &amg into params (which keeps its defaults for what the deck leaves out).
  subroutine read_amg_config(d, log, params, status)
    type(deck_t), intent(in) :: d
    type(logger_t), intent(inout) :: log
    type(amg_params_t), intent(inout) :: params
    type(error_status_t), intent(inout) :: status
    integer :: num_functions, nodal, p_max_elmts, agg_num_levels, agg_p_max_elmts, num_paths, &
               max_levels, max_coarse_size, num_sweeps, print_level, interp_vec_variant, interp_vec_qmax, ios
    character(len=name_len) :: coarsen_type, interp_type, agg_interp_type, relax_type, cycle_type, relax_order, &
                               cycle_code, precision
    real(rp) :: trunc_factor, strong_threshold, max_row_sum, relax_wt, slab_threshold
    type(error_status_t) :: vstat
    character(len=msg_len) :: msg
    character(len=line_len), allocatable :: b(:)
    namelist /amg/ num_functions, nodal, coarsen_type, interp_type, p_max_elmts, trunc_factor, &
                   agg_num_levels, agg_interp_type, agg_p_max_elmts, num_paths, strong_threshold, &
                   max_row_sum, max_levels, max_coarse_size, relax_type, num_sweeps, relax_wt, print_level, &
                   interp_vec_variant, interp_vec_qmax, cycle_type, slab_threshold, relax_order, cycle_code, &
                   precision

    num_functions = params%num_functions; nodal = params%nodal; coarsen_type = params%coarsen_type
    interp_type = params%interp_type; p_max_elmts = params%p_max_elmts; trunc_factor = params%trunc_factor
    agg_num_levels = params%agg_num_levels; agg_interp_type = params%agg_interp_type
    agg_p_max_elmts = params%agg_p_max_elmts; num_paths = params%num_paths
    strong_threshold = params%strong_threshold; max_row_sum = params%max_row_sum
    max_levels = params%max_levels; max_coarse_size = params%max_coarse_size; relax_type = params%relax_type
    num_sweeps = params%num_sweeps; relax_wt = params%relax_wt; print_level = params%print_level
    interp_vec_variant = params%interp_vec_variant; interp_vec_qmax = params%interp_vec_qmax
    cycle_type = params%cycle_type; slab_threshold = params%slab_threshold; relax_order = params%relax_order
    cycle_code = params%cycle_code; precision = params%precision
    if (d%count('amg') > 0) then
      call d%block('amg', 1, b)
      read(b, nml=amg, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call d%read_error('amg', 1, ios, msg, status)
        return
      end if
    end if
    params = amg_params_t(num_functions=num_functions, nodal=nodal, coarsen_type=coarsen_type, &
      interp_type=interp_type, p_max_elmts=p_max_elmts, trunc_factor=trunc_factor, &
      agg_num_levels=agg_num_levels, agg_interp_type=agg_interp_type, agg_p_max_elmts=agg_p_max_elmts, &
      num_paths=num_paths, strong_threshold=strong_threshold, max_row_sum=max_row_sum, &
      max_levels=max_levels, max_coarse_size=max_coarse_size, relax_type=relax_type, relax_order=relax_order, &
      num_sweeps=num_sweeps, relax_wt=relax_wt, print_level=print_level, &
      interp_vec_variant=interp_vec_variant, interp_vec_qmax=interp_vec_qmax, cycle_type=cycle_type, &
      slab_threshold=slab_threshold, cycle_code=cycle_code, precision=precision)
    call params%validate(vstat)
    if (.not. vstat%ok()) then
      write(msg, '(a,i0,a)') "deck '"//trim(d%path)//"', group &amg (line ", d%first_line('amg', 1), "): "// &
        trim(vstat%msg(len('amg_params: ') + 1:))
      call status%set(msg)
      return
    end if
  end subroutine read_amg_config

  !> The resolved &amg group of params (meanings, hypre ids and the reasons
  !> for the defaults: amg_params.f90).
  subroutine describe_amg_config(params, g)
    type(amg_params_t), intent(in) :: params
    type(param_group_t), intent(out) :: g
    call g%init('amg', 'the BoomerAMG settings of every AMG in the run (defaults for 3D Q1 elasticity; Schur '// &
                'complements and pressure Laplacians take a scalar copy)')
    call g%add('num_functions', params%num_functions, '-', 'unknowns per node (systems AMG)', '1..64')
    call g%add('nodal', params%nodal, '-', '0 unknown approach; 1-4, 6 nodal norms', &
               '0, 1, 2, 3, 4 or 6; 0 when num_functions = 1')
    call g%add('coarsen_type', params%coarsen_type, '-', 'coarsening', &
               "'cljp', 'ruge-stueben', 'falgout', 'pmis' or 'hmis'")
    call g%add('interp_type', params%interp_type, '-', 'interpolation', "'classical', 'direct', 'multipass', "// &
               "'ext+i', 'standard', 'ff1', 'ext', 'ext-mm', 'ext+i-mm' or 'ext+e-mm'")
    call g%add('p_max_elmts', params%p_max_elmts, '-', 'interpolation entries per row (0: all)', '0..100')
    call g%add('trunc_factor', params%trunc_factor, '-', 'interpolation truncation factor', '[0, 1)')
    call g%add('agg_num_levels', params%agg_num_levels, '-', 'levels of aggressive coarsening', &
               '0..max_levels - 1')
    call g%add('agg_interp_type', params%agg_interp_type, '-', 'interpolation of the aggressive levels', &
               "'2s-ext+i', '2s-standard', '2s-ext', 'multipass', '2s-ext-mm', '2s-ext+i-mm' or '2s-ext+e-mm'")
    call g%add('agg_p_max_elmts', params%agg_p_max_elmts, '-', 'entries per row, aggressive levels (0: all)', &
               '0..100')
    call g%add('num_paths', params%num_paths, '-', 'paths of aggressive coarsening', '1..10')
    call g%add('strong_threshold', params%strong_threshold, '-', 'strength of connection', '(0, 1)')
    call g%add('max_row_sum', params%max_row_sum, '-', 'weakens diagonally dominant rows (1: off)', '(0, 1]')
    call g%add('max_levels', params%max_levels, '-', 'largest number of levels', '1..100')
    call g%add('max_coarse_size', params%max_coarse_size, '-', 'rows of the coarsest level', '>= 1')
    call g%add('relax_type', params%relax_type, '-', "smoother (every one symmetric: fit for CG)", &
               "'jacobi', 'hybrid-gs', 'hybrid-sgs', 'l1-sgs', 'l1-gs', 'chebyshev' or 'l1-jacobi'")
    call g%add('relax_order', params%relax_order, '-', 'order of the Gauss-Seidel sweeps: the rows in their '// &
               "order, or hypre's C points then F points", "'lexicographic' or 'cf'")
    call g%add('num_sweeps', params%num_sweeps, '-', 'smoothing sweeps down and up', '1..20')
    call g%add('relax_wt', params%relax_wt, '-', 'weight of Jacobi / SOR smoothers', '(0, 2)')
    call g%add('print_level', params%print_level, '-', "hypre's own output: 0 none .. 3", '0..3')
    call g%add('cycle_type', params%cycle_type, '-', 'V- or W-cycle', "'v' or 'w'")
    call g%add('interp_vec_variant', params%interp_vec_variant, '-', 'rigid-body modes in the interpolation of '// &
               'K (and S*): 0 none, 1, 2 GM, 3 LN', '0..3; 0 when nodal = 0')
    call g%add('interp_vec_qmax', params%interp_vec_qmax, '-', 'entries per row of the added columns (0: all)', &
               '0..100')
    call g%add('cycle_code', params%cycle_code, '-', "the code that runs the cycle: geoblock's over hypre's "// &
               "hierarchy (l1-gs V-cycles, lexicographic order, unit weights; its backward sweep reads memory "// &
               "downwards: half the solve time of hypre's on elasticity), hypre's own for other settings", &
               "'geoblock' or 'hypre'")
    call g%add('precision', params%precision, '-', "the level matrices' values in geoblock's cycle: double, "// &
               "or single (floats: 8 bytes an entry with its column index instead of 12, summed in double; every "// &
               "level converted in place, no new memory; a level beyond single precision's range stays double)", &
               "'double' or 'single'")
    call g%add('slab_threshold', params%slab_threshold, '-', 'strength threshold, at least, of the displacement '// &
               'block (K, S*) on a slab with flat cells (found from the mesh; 0: as strong_threshold)', '[0, 1)')
  end subroutine describe_amg_config
end module amg_config
