!> Fluid flow along the fractures: one pressure p per interface element (P0,
!> the rock matrix is impermeable), two-point fluxes between neighbouring
!> elements across their shared edges (fault_edges), with the cubic law for
!> the hydraulic aperture a = g_N + a0 of an open element (a0, the residual
!> aperture from the deck, lets a closed fracture conduct; set_apertures).
!>
!> Parallel plates a apart carry, per unit width, the flow a^3 / (12 mu) times
!> the pressure gradient (the cubic law, e.g. Witherspoon et al., Water
!> Resour. Res. 16 (1980) 1016). Over an edge of length L, between element
!> centres d1 and d2 from it, the half transmissibilities and the edge's are
!>   T_i = a_i^3 L / (12 mu d_i)  [m^3 / (Pa s)],   T = T_1 T_2 / (T_1 + T_2),
!> (harmonic: the two halves in series), and the volume flux from element 1
!> to element 2 is T (p_1 - p_2) [m^3/s]. With one aperture a on both sides,
!> T = a^3 L / (12 mu (d1 + d2)): the cubic law exactly for a uniform
!> gradient. The matrix T of the mass balance (row e: sum over e's edges of
!> T (p_e - p_f)) is symmetric, its rows sum to zero, and it conserves mass
!> edge by edge. Edges at a tip carry no flow; junctions of three or more
!> fault elements are not edges (fault_edges), so intersecting faults do not
!> exchange fluid (a limit of this version).
module fracture_flow
  use kinds, only: rp, ip
  use csr_matrix, only: csr_matrix_t
  use dist_mesh, only: dist_mesh_t
  use sparsity, only: element_pattern
  use fault_edges, only: fault_edges_t
  implicit none
  private

  public :: fracture_flow_t, edge_transmissibility

  type :: fracture_flow_t
    real(rp) :: mu = 1.0e-3_rp                  !< fluid viscosity [Pa s]
    real(rp) :: a0 = 0.0_rp                     !< residual hydraulic aperture [m]
    real(rp), allocatable :: aperture(:)        !< (n_ifaces) hydraulic aperture a [m]
    real(rp), allocatable :: da_dg(:)           !< (n_ifaces) d a / d g_N: 1 open, 0 closed
    real(rp), allocatable :: trans(:)           !< (n_edges) T [m^3/(Pa s)]
    real(rp), allocatable :: dtrans(:,:)        !< (2, n_edges) d T / d a of the edge's two elements
  contains
    procedure :: init
    procedure :: set_apertures
    procedure :: pattern
    procedure :: assemble_t
    procedure :: edge_fluxes
    procedure :: element_flux
    procedure :: free
  end type fracture_flow_t

contains

  !> Viscosity mu [Pa s] and residual aperture a0 [m]; apertures start at a0.
  subroutine init(self, mesh, edges, mu, a0)
    class(fracture_flow_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(fault_edges_t), intent(in) :: edges
    real(rp), intent(in) :: mu, a0
    call self%free()
    self%mu = mu
    self%a0 = a0
    allocate(self%aperture(mesh%n_ifaces), self%da_dg(mesh%n_ifaces))
    allocate(self%trans(edges%n), self%dtrans(2, edges%n))
    call self%set_apertures(edges, spread(0.0_rp, 1, mesh%n_ifaces), spread(.false., 1, mesh%n_ifaces))
  end subroutine init

  !> Apertures from the normal jumps g_N (local elements, ghosts included)
  !> and the edges' transmissibilities with their derivatives. An open
  !> element (is_open) has a = a0 + g_N for g_N >= 0 and a0 exp(g_N / a0)
  !> below: the same value and slope at g_N = 0, so the aperture of an open
  !> element is smooth in its jump, and Newton does not meet a kink where an
  !> iterate's g_N crosses zero before the active set closes it. (With the
  !> kink, a = max(g_N, 0) + a0, an open fracture of a0 1e-5 m in 1 m
  !> elements cycled with period 8 through 30 Newton iterations, its
  !> statuses fixed.) A closed element conducts with a0 alone: its normal
  !> jump is the stabilization's allowance, not an opening.
  subroutine set_apertures(self, edges, gn, is_open)
    class(fracture_flow_t), intent(inout) :: self
    type(fault_edges_t), intent(in) :: edges
    real(rp), intent(in) :: gn(:)
    logical, intent(in) :: is_open(:)
    integer(ip) :: ed, e
    do e = 1, size(gn)
      if (.not. is_open(e)) then
        self%aperture(e) = self%a0
        self%da_dg(e) = 0.0_rp
      else if (gn(e) >= 0.0_rp) then
        self%aperture(e) = gn(e) + self%a0
        self%da_dg(e) = 1.0_rp
      else if (self%a0 > 0.0_rp) then
        self%aperture(e) = self%a0 * exp(gn(e) / self%a0)
        self%da_dg(e) = self%aperture(e) / self%a0
      else
        self%aperture(e) = 0.0_rp
        self%da_dg(e) = 0.0_rp
      end if
    end do
    do ed = 1, edges%n
      associate (e1 => edges%pair(1, ed), e2 => edges%pair(2, ed))
        call edge_transmissibility(edges%length(ed), edges%dist(1, ed), edges%dist(2, ed), &
                                   self%aperture(e1), self%aperture(e2), self%mu, self%trans(ed), self%dtrans(:, ed))
      end associate
    end do
  end subroutine set_apertures

  !> T = T1 T2 / (T1 + T2) with T_i = a_i^3 L / (12 mu d_i), and dT/da_i;
  !> T = 0 (and its derivatives) when an aperture is zero.
  pure subroutine edge_transmissibility(length, d1, d2, a1, a2, mu, t, dt)
    real(rp), intent(in) :: length, d1, d2, a1, a2, mu
    real(rp), intent(out) :: t, dt(2)
    real(rp) :: t1, t2
    t1 = a1**3 * length / (12.0_rp * mu * d1)
    t2 = a2**3 * length / (12.0_rp * mu * d2)
    if (t1 <= 0.0_rp .or. t2 <= 0.0_rp) then
      t = 0.0_rp
      dt = 0.0_rp
      return
    end if
    t = t1 * t2 / (t1 + t2)
    ! dT/dT1 = (T / T1)^2, dT1/da1 = 3 T1 / a1
    dt(1) = (t / t1)**2 * 3.0_rp * t1 / a1
    dt(2) = (t / t2)**2 * 3.0_rp * t2 / a2
  end subroutine edge_transmissibility

  !> CSR pattern of T on the owned elements (each element and its edge
  !> neighbours), local column ids.
  subroutine pattern(self, mesh, edges, row_ptr, col, extra)
    class(fracture_flow_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(fault_edges_t), intent(in) :: edges
    integer(ip), allocatable, intent(out) :: row_ptr(:), col(:)
    integer(ip), intent(in), optional :: extra(:,:)   !< (2, n) further pairs of coupled local ids
    integer(ip), allocatable :: pairs(:,:)
    integer(ip) :: e, n
    n = mesh%n_ifaces
    allocate(pairs(2, n + edges%n))
    pairs(:, 1:n) = spread([(e, e = 1, n)], 1, 2)
    pairs(:, n+1:) = edges%pair
    if (present(extra)) pairs = reshape([pairs, extra], [2, size(pairs, 2) + size(extra, 2)])
    call element_pattern(mesh%iface_map%n_owned, pairs, pairs, 1_ip, 1_ip, row_ptr, col)
  end subroutine pattern

  !> tmat = T (zeroed first) on the rows of the owned elements; tmat has the
  !> pattern of pattern(). Local: no communication.
  subroutine assemble_t(self, mesh, edges, tmat)
    class(fracture_flow_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(fault_edges_t), intent(in) :: edges
    type(csr_matrix_t), intent(inout) :: tmat
    integer(ip) :: ed, s, e, o, nown
    nown = mesh%iface_map%n_owned
    call tmat%zero()
    do ed = 1, edges%n
      do s = 1, 2
        e = edges%pair(s, ed)
        o = edges%pair(3 - s, ed)
        if (e > nown) cycle
        call tmat%add_value(e, e, self%trans(ed))
        call tmat%add_value(e, o, -self%trans(ed))
      end do
    end do
  end subroutine assemble_t

  !> Volume flux [m^3/s] across every edge from pair(1) to pair(2), for the
  !> pressures p of the local elements (ghosts current).
  function edge_fluxes(self, edges, p) result(q)
    class(fracture_flow_t), intent(in) :: self
    type(fault_edges_t), intent(in) :: edges
    real(rp), intent(in) :: p(:)
    real(rp) :: q(edges%n)
    q = self%trans * (p(edges%pair(1, :)) - p(edges%pair(2, :)))
  end function edge_fluxes

  !> The flow vector of every owned element [m^2/s] (volume flux per unit
  !> width of the fracture): the lowest-order reconstruction from its edge
  !> fluxes, v = sum over its edges of q_out (x_edge - x_centre) / A, exact
  !> for a uniform flow on a parallelogram when every edge's flux is known
  !> (an edge at a tip or junction carries none).
  function element_flux(self, mesh, edges, p) result(v)
    class(fracture_flow_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(fault_edges_t), intent(in) :: edges
    real(rp), intent(in) :: p(:)
    real(rp), allocatable :: v(:,:)
    real(rp) :: q(edges%n), x(3, 4), c(3), m(3), area
    integer(ip) :: e, k, ed
    integer :: s
    allocate(v(3, mesh%iface_map%n_owned))
    q = self%edge_fluxes(edges, p)
    do e = 1, mesh%iface_map%n_owned
      x = mesh%coords(:, mesh%iface_nodes(:, 1, e))
      c = sum(x, dim=2) / 4.0_rp
      area = 0.5_rp * norm2(cross3(x(:, 3) - x(:, 1), x(:, 4) - x(:, 2)))
      v(:, e) = 0.0_rp
      do k = 1, 4
        ed = edges%of_elem(k, e)
        if (ed == 0) cycle
        s = merge(1, -1, edges%pair(1, ed) == e)          ! q is from pair(1) to pair(2)
        m = 0.5_rp * (x(:, k) + x(:, mod(k, 4) + 1))
        v(:, e) = v(:, e) + s * q(ed) * (m - c) / area
      end do
    end do
  contains
    pure function cross3(a, b) result(w)
      real(rp), intent(in) :: a(3), b(3)
      real(rp) :: w(3)
      w = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
    end function cross3
  end function element_flux

  subroutine free(self)
    class(fracture_flow_t), intent(inout) :: self
    if (allocated(self%aperture)) deallocate(self%aperture, self%da_dg)
    if (allocated(self%trans)) deallocate(self%trans, self%dtrans)
  end subroutine free
end module fracture_flow
