!> Fracture flow kernel (fault_edges, fracture_flow) on a distributed mesh:
!>  - the edges of a through-going fracture of 8 x 2 elements: count (global),
!>    lengths and centre distances;
!>  - the cubic law: a uniform aperture a under a uniform pressure gradient G
!>    along the fracture carries a^3 L G / (12 mu) through every edge of
!>    length L across the flow, i.e. w a^3 dp / (12 mu L) through the whole
!>    width w, to 1e-12 relative; no flow along the contour lines;
!>  - T conserves mass: T 1 = 0, the sum of T p over the fracture is zero,
!>    interior rows balance, the end rows give the end fluxes;
!>  - the aperture law (open: g_N + a0, closed: a0) and dT/da against
!>    central differences.
!> Run on 1 and 2 ranks (edges across the partition); from the repository root.
program test_fracture_flow
  use kinds, only: rp, ip
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use deck, only: deck_t
  use mesh_config, only: mesh_config_t
  use fault_config, only: fault_config_t, read_faults
  use mesh_builder, only: build_mesh
  use dist_mesh, only: dist_mesh_t
  use csr_matrix, only: csr_matrix_t
  use fault_edges, only: fault_edges_t
  use fracture_flow, only: fracture_flow_t, edge_transmissibility
  use assertions, only: test_suite_t
  use deck_files, only: write_lines
  implicit none

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(logger_t) :: log
  type(error_status_t) :: st
  type(dist_mesh_t) :: dm
  type(fault_config_t), allocatable :: faults(:)
  type(fault_edges_t) :: edges
  type(fracture_flow_t) :: flow
  type(csr_matrix_t) :: tmat
  integer(ip), allocatable :: row_ptr(:), col(:)
  real(rp), allocatable :: p(:), tp(:), ones(:), q(:), yc(:), zc(:), vflux(:,:)
  real(rp), parameter :: mu = 2.0e-3_rp, a = 1.0e-4_rp, a0 = 1.0e-5_rp, grad = 3.0e5_rp, p0 = 1.0e7_rp
  character(len=64) :: tmp_deck
  real(rp) :: half, expect, worst, worst_z, t, dt(2), tp_, tm_, fd, total, scale, end_flux
  integer(ip) :: ed, e, nown, n_y, n_z
  logical :: ok

  call comm%init_world()
  call suite%init('fracture_flow', comm)
  call log%init(comm, 0)
  write(tmp_deck, '(a,i0,a)') '/tmp/test_fracture_flow_', comm%size, '.nml'

  ! a fracture x = 0.5 through the box [0,1] x [0,2] x [0,0.5], 8 x 2 elements of 0.25 x 0.25
  call write_lines(comm, tmp_deck, [character(len=100) :: "&mesh source = 'box', nx = 4, ny = 8, nz = 2,", &
                   "      upper = 1.0, 2.0, 0.5 /", "&fault name = 'frac', normal_axis = 'x', position = 0.5 /"])
  call build_from_deck(st)
  call suite%assert_true(st%ok(), 'mesh with the fracture built: '//trim(st%msg))
  if (.not. st%ok()) call suite%finish()
  nown = dm%iface_map%n_owned
  call suite%assert_equal_int(int(dm%iface_map%n_global), 16, '16 interface elements')

  ! ---- edges ------------------------------------------------------------------------------------
  call edges%build(dm)
  half = 0.0_rp
  do ed = 1, edges%n
    half = half + 0.5_rp * real(count(edges%pair(:, ed) <= nown), rp)
  end do
  call suite%assert_close(comm%sum(half), 22.0_rp, 0.0_rp, 'edges: 7 x 2 along y + 8 along z = 22 (global)')
  call suite%assert_true(edges%n == 0 .or. (all(abs(edges%length - 0.25_rp) < 1.0e-14_rp) .and. &
                         all(abs(edges%dist - 0.125_rp) < 1.0e-14_rp)), 'edges: length 0.25, centre distances 0.125')
  ok = .true.
  do ed = 1, edges%n
    ok = ok .and. edges%pair(1, ed) < edges%pair(2, ed) .and. &
         edges%of_elem(edges%side(1, ed), edges%pair(1, ed)) == ed .and. &
         edges%of_elem(edges%side(2, ed), edges%pair(2, ed)) == ed
  end do
  call suite%assert_true(ok, 'edges: pairs ordered, sides and of_elem consistent')

  ! ---- the cubic law ----------------------------------------------------------------------------
  call flow%init(dm, edges, mu, a0)
  call flow%set_apertures(edges, spread(a - a0, 1, dm%n_ifaces), spread(.true., 1, dm%n_ifaces))
  call suite%assert_true(all(abs(flow%aperture - a) < 1.0e-18_rp) .and. all(flow%da_dg == 1.0_rp), &
                         'aperture: open, a = g_N + a0')
  allocate(yc(dm%n_ifaces), zc(dm%n_ifaces), p(dm%n_ifaces))
  do e = 1, dm%n_ifaces
    yc(e) = sum(dm%coords(2, dm%iface_nodes(:, 1, e))) / 4.0_rp
    zc(e) = sum(dm%coords(3, dm%iface_nodes(:, 1, e))) / 4.0_rp
  end do
  p = p0 - grad * yc
  q = flow%edge_fluxes(edges, p)
  expect = a**3 * 0.25_rp * grad / (12.0_rp * mu)       ! per edge of length 0.25 across the flow
  worst = 0.0_rp
  worst_z = 0.0_rp
  n_y = 0
  n_z = 0
  do ed = 1, edges%n
    associate (e1 => edges%pair(1, ed), e2 => edges%pair(2, ed))
      if (abs(yc(e1) - yc(e2)) > 1.0e-12_rp) then     ! an edge across the flow
        worst = max(worst, abs(abs(q(ed)) - expect) / expect)
        ok = ok .and. (q(ed) > 0.0_rp .eqv. yc(e1) < yc(e2))
        n_y = n_y + 1
      else
        worst_z = max(worst_z, abs(q(ed)) / expect)
        n_z = n_z + 1
      end if
    end associate
  end do
  worst = comm%max(worst)
  worst_z = comm%max(worst_z)
  call suite%assert_close(worst, 0.0_rp, 1.0e-12_rp, 'cubic law: every edge across the flow carries '// &
                          'a^3 L G / (12 mu), so the width w = 0.5 carries w a^3 dp / (12 mu L)')
  call suite%assert_close(worst_z, 0.0_rp, 1.0e-12_rp, 'cubic law: no flow along the contour lines')
  call suite%assert_true(ok, 'cubic law: the flow goes down the gradient')

  ! ---- the element flow vectors: interior elements carry a^3 G / (12 mu) along -y exactly; the
  ! ---- end elements (a fracture edge without flux on one side) half of it
  vflux = flow%element_flux(dm, edges, p)
  worst = 0.0_rp
  ok = .true.
  do e = 1, nown
    if (yc(e) > 0.125_rp + 1.0e-12_rp .and. yc(e) < 1.875_rp - 1.0e-12_rp) then
      worst = max(worst, norm2(vflux(:, e) - [0.0_rp, grad * a**3 / (12.0_rp * mu), 0.0_rp]) / &
                         (grad * a**3 / (12.0_rp * mu)))
    else
      ok = ok .and. abs(norm2(vflux(:, e)) - 0.5_rp * grad * a**3 / (12.0_rp * mu)) <= 1.0e-12_rp * grad * a**3 / mu
    end if
  end do
  call suite%assert_close(comm%max(worst), 0.0_rp, 1.0e-12_rp, 'element flow vectors: a^3 G / (12 mu) along '// &
                          'the gradient in the interior (per unit width)')
  call suite%assert_true(.not. comm%any_true(.not. ok), 'element flow vectors: half of it at the ends (no flux '// &
                         'through the fracture''s edge)')

  ! ---- T: conservation --------------------------------------------------------------------------
  call flow%pattern(dm, edges, row_ptr, col)
  call tmat%init(dm%iface_map, dm%iface_map, row_ptr, col)
  call flow%assemble_t(dm, edges, tmat)
  allocate(tp(nown), ones(nown))
  ones = 1.0_rp
  call tmat%apply(ones, tp)
  scale = maxval(flow%trans) * p0
  call suite%assert_close(comm%max(maxval(abs(tp)) * p0 / max(scale, tiny(1.0_rp))), &
                          0.0_rp, 1.0e-12_rp, 'T 1 = 0 (rows sum to zero)')
  call tmat%apply(p(1:nown), tp)
  total = comm%sum(sum(tp))
  end_flux = 2.0_rp * expect                            ! through the width: two edges of 0.25
  call suite%assert_close(total / end_flux, 0.0_rp, 1.0e-12_rp, 'sum of T p over the fracture = 0 (conservation)')
  worst = 0.0_rp
  ok = .true.
  do e = 1, nown
    if (yc(e) > 0.125_rp + 1.0e-12_rp .and. yc(e) < 1.875_rp - 1.0e-12_rp) then
      worst = max(worst, abs(tp(e)) / expect)
    else                                                ! an end element: its one flux leaves or enters
      ok = ok .and. abs(abs(tp(e)) - expect) <= 1.0e-12_rp * expect
    end if
  end do
  call suite%assert_close(comm%max(worst), 0.0_rp, 1.0e-12_rp, 'interior rows of T p balance (in = out)')
  call suite%assert_true(.not. comm%any_true(.not. ok), 'end rows of T p = the flux through their one edge')

  ! ---- the aperture law and dT/da ---------------------------------------------------------------
  call flow%set_apertures(edges, spread(1.0e-3_rp, 1, dm%n_ifaces), spread(.false., 1, dm%n_ifaces))
  call suite%assert_true(all(abs(flow%aperture - a0) < 1.0e-20_rp) .and. all(flow%da_dg == 0.0_rp), &
                         'aperture: closed (whatever its jump), a = a0 (the residual aperture), da/dg_N = 0')
  ! an open element below g_N = 0: a0 exp(g_N / a0), continuous in value
  ! and slope at 0, its derivative the central difference's
  call flow%set_apertures(edges, spread(-0.5_rp * a0, 1, dm%n_ifaces), spread(.true., 1, dm%n_ifaces))
  call suite%assert_true(all(abs(flow%aperture - a0 * exp(-0.5_rp)) < 1.0e-15_rp * a0) .and. &
                         all(abs(flow%da_dg - exp(-0.5_rp)) < 1.0e-15_rp), &
                         'aperture: open with g_N = -a0/2, a = a0 exp(g_N/a0), da/dg_N = exp(g_N/a0)')
  block
    real(rp), allocatable :: am(:), ap(:), dm_(:), dp_(:)
    call flow%set_apertures(edges, spread(-1.0e-9_rp * a0, 1, dm%n_ifaces), spread(.true., 1, dm%n_ifaces))
    am = flow%aperture
    dm_ = flow%da_dg
    call flow%set_apertures(edges, spread(1.0e-9_rp * a0, 1, dm%n_ifaces), spread(.true., 1, dm%n_ifaces))
    ap = flow%aperture
    dp_ = flow%da_dg
    call suite%assert_true(.not. comm%any_true(.not. (all(abs(ap - am) <= 3.0e-9_rp * a0) .and. &
                           all(abs(dp_ - dm_) <= 1.0e-8_rp) .and. &
                           all(abs((ap - am) / (2.0e-9_rp * a0) - 1.0_rp) <= 1.0e-6_rp))), &
                           'aperture: open, value and slope continuous at g_N = 0')
  end block
  call edge_transmissibility(0.3_rp, 0.1_rp, 0.2_rp, 1.0e-4_rp, 3.0e-4_rp, mu, t, dt)
  ok = .true.
  do e = 1, 2
    call edge_transmissibility(0.3_rp, 0.1_rp, 0.2_rp, 1.0e-4_rp + merge(1.0e-9_rp, 0.0_rp, e == 1), &
                               3.0e-4_rp + merge(1.0e-9_rp, 0.0_rp, e == 2), mu, tp_, dt)
    call edge_transmissibility(0.3_rp, 0.1_rp, 0.2_rp, 1.0e-4_rp - merge(1.0e-9_rp, 0.0_rp, e == 1), &
                               3.0e-4_rp - merge(1.0e-9_rp, 0.0_rp, e == 2), mu, tm_, dt)
    fd = (tp_ - tm_) / 2.0e-9_rp
    call edge_transmissibility(0.3_rp, 0.1_rp, 0.2_rp, 1.0e-4_rp, 3.0e-4_rp, mu, t, dt)
    ok = ok .and. abs(dt(e) - fd) <= 1.0e-6_rp * abs(fd)
  end do
  call suite%assert_true(ok, 'dT/da of both elements = central differences (1e-6)')
  call suite%assert_close(t, 1.0_rp / (12.0_rp * mu * 0.1_rp / (1.0e-12_rp * 0.3_rp) + &
                          12.0_rp * mu * 0.2_rp / (2.7e-11_rp * 0.3_rp)), 1.0e-12_rp * t, &
                          'T = harmonic combination of a^3 L / (12 mu d) of the halves')
  call edge_transmissibility(0.3_rp, 0.1_rp, 0.2_rp, 0.0_rp, 3.0e-4_rp, mu, t, dt)
  call suite%assert_true(t == 0.0_rp .and. all(dt == 0.0_rp), 'a zero aperture on one side: no flow')

  call flow%free()
  call edges%free()
  call tmat%free()
  call dm%free()
  call suite%finish()

contains

  subroutine build_from_deck(st)
    type(error_status_t), intent(out) :: st
    type(deck_t) :: d
    type(mesh_config_t) :: cfg
    call d%load(comm, tmp_deck, st)
    if (st%ok()) call cfg%read(d, log, st)
    if (st%ok()) call read_faults(d, log, faults, st, cfg%source)
    if (st%ok()) call build_mesh(comm, cfg, log, dm, st, faults)
  end subroutine build_from_deck

end program test_fracture_flow
