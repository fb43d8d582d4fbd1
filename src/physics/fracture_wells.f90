!> Wells of the fluid in the fractures: where each &well meets the fractures
!> (its connections) and the rates it gives them.
!>
!> A well at a point has one connection, the element whose centre is nearest
!> to the point, and injects its whole rate Q there. A well along a segment
!> has one connection per fault it crosses (the crossed element of lowest
!> original id where the segment passes through an edge or a node). Its
!> wellbore is one pressure p_w (no friction along the well), and the
!> connection c takes q_c = J_c (p_w - p_c) with sum_c q_c = Q: eliminating
!> p_w,
!>   p_w = (Q + sum_d J_d p_d) / sum_d J_d,
!>   q_c = J_c Q / sum_d J_d + J_c (sum_d J_d p_d / sum_d J_d - p_c),
!> so the rate goes where the pressure is low and the aperture wide, the
!> rates sum to Q exactly, and the mass rows get the symmetric coupling
!> J_c J_d / sum J - delta_cd J_c among the well's elements (like extra
!> transmissibilities; the pressure map carries the other connections'
!> elements as ghosts on the ranks that own one).
!>
!> The connection index J is the deck's `index`, or Peaceman's for a well
!> across a layer of transmissivity a^3 / 12 (the cubic law; Peaceman, SPE J.
!> 23 (1983) 531, isotropic case):
!>   J = 2 pi a^3 / (12 mu ln(r_e / r_w)),   r_e = 0.14 sqrt(dx^2 + dy^2),
!> dx, dy the element's mid-line lengths (r_e = 0.198 dx on a square), r_w
!> the well radius, a the element's hydraulic aperture at the start of the
!> step (J is held through the step's Newton iterations).
module fracture_wells
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use dist_mesh, only: dist_mesh_t
  use flow_config, only: well_config_t
  use strings, only: rtoa
  implicit none
  private

  public :: well_links_t

  real(rp), parameter :: pi = acos(-1.0_rp)

  type :: well_links_t
    type(parallel_comm_t) :: comm
    integer, allocatable :: first(:)       !< (wells + 1) connections first(k) .. first(k+1) - 1 of well k
    logical, allocatable :: along(:)       !< (wells) along a segment: the rate split by the indices
    real(rp), allocatable :: radius(:), index(:)   !< (wells) r_w [m], the deck's J (0: Peaceman's)
    real(rp), allocatable :: q(:)          !< (wells) rate of the step [m^3/s]
    integer, allocatable :: fault(:)       !< (connections) fault of the element (mesh%fault_names)
    integer(gp), allocatable :: gid(:)     !< (connections) global id of the element
    integer(ip), allocatable :: elem(:)    !< (connections) local id in the pressure map, 0: no copy here
    logical, allocatable :: mine(:)        !< (connections) the element is owned here
    real(rp), allocatable :: centre(:,:)   !< (3, connections) element centre [m]
    real(rp), allocatable :: r_e(:)        !< (connections) Peaceman's equivalent radius [m]
    real(rp), allocatable :: j(:)          !< (connections) connection index of the step [m^3/(Pa s)]
  contains
    procedure :: locate
    procedure :: extra_ghosts
    procedure :: set_local
    procedure :: pairs
    procedure :: begin_step
    procedure :: add_mass_terms
    procedure :: rates
    procedure :: bottom_hole
    procedure :: n_conn
    procedure :: free
  end type well_links_t

contains

  !> Find every well's connections (the same on every rank) and check the
  !> radius against each element's equivalent radius. Collective.
  subroutine locate(self, mesh, wells, status)
    class(well_links_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    type(well_config_t), intent(in) :: wells(:)
    type(error_status_t), intent(inout) :: status
    integer(gp), allocatable :: best(:)
    integer :: k, nf, c, nc
    call self%free()
    self%comm = mesh%comm
    nf = size(mesh%fault_names)
    allocate(self%first(size(wells) + 1), self%along(size(wells)), self%q(size(wells)))
    allocate(self%radius(size(wells)), self%index(size(wells)))
    allocate(self%fault(0), self%gid(0))
    self%q = 0.0_rp
    self%first(1) = 1
    do k = 1, size(wells)
      self%along(k) = wells(k)%along
      self%radius(k) = wells(k)%radius
      self%index(k) = wells(k)%index
      if (wells(k)%along) then
        best = crossed(mesh, wells(k)%segment, nf)
      else
        best = [nearest_element(mesh, wells(k)%point)]
      end if
      do c = 1, size(best)
        if (best(c) == 0) cycle
        self%gid = [self%gid, best(c)]
        self%fault = [self%fault, merge(c, 0, wells(k)%along)]
      end do
      self%first(k + 1) = size(self%gid) + 1
      if (self%first(k + 1) == self%first(k)) then
        call status%set("&well '"//trim(wells(k)%name)//"': its segment from ("//trim(coords(wells(k)%segment(1:3)))// &
                        ") to ("//trim(coords(wells(k)%segment(4:6)))//") crosses no fault", 2)
        return
      end if
    end do
    nc = size(self%gid)
    allocate(self%elem(nc), self%mine(nc), self%centre(3, nc), self%r_e(nc), self%j(nc))
    self%centre = 0.0_rp
    self%r_e = 0.0_rp
    self%j = 0.0_rp
    do c = 1, nc
      self%mine(c) = mesh%iface_map%local_id(self%gid(c)) >= 1 .and. &
                     mesh%iface_map%local_id(self%gid(c)) <= mesh%iface_map%n_owned
      if (.not. self%mine(c)) cycle
      associate (e => mesh%iface_map%local_id(self%gid(c)))
        if (self%fault(c) == 0) self%fault(c) = mesh%iface_fault(e)
        self%centre(:, c) = centre_of(mesh, e)
        self%r_e(c) = equivalent_radius(mesh, e)
      end associate
    end do
    ! the point wells' faults, centres and radii, known on every rank
    call self%comm%sum_all(self%centre(1, :))
    call self%comm%sum_all(self%centre(2, :))
    call self%comm%sum_all(self%centre(3, :))
    call self%comm%sum_all(self%r_e)
    block
      integer, allocatable :: f(:)
      f = merge(self%fault, 0, self%mine)
      call self%comm%sum_all(f)
      self%fault = f
    end block
    do k = 1, size(wells)
      if (.not. wells(k)%along .or. wells(k)%index > 0.0_rp) cycle
      do c = self%first(k), self%first(k + 1) - 1
        if (.not. self%r_e(c) > wells(k)%radius) then
          call status%set("&well '"//trim(wells(k)%name)//"': radius "//rtoa(wells(k)%radius)// &
            " m is not below the equivalent radius "//rtoa(self%r_e(c))//" m of its element on fault '"// &
            trim(mesh%fault_names(self%fault(c)))//"' (Peaceman: 0.14 sqrt(dx^2 + dy^2)); give a smaller "// &
            "radius or the connection index", 2)
          return
        end if
      end do
    end do
  end subroutine locate

  !> The global ids of the elements this rank needs as extra pressure
  !> ghosts: the other connections of every well it owns a connection of.
  function extra_ghosts(self, mesh) result(g)
    class(well_links_t), intent(in) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(gp), allocatable :: g(:)
    integer :: k, c
    allocate(g(0))
    do k = 1, size(self%along)
      if (.not. any(self%mine(self%first(k):self%first(k + 1) - 1))) cycle
      do c = self%first(k), self%first(k + 1) - 1
        if (mesh%iface_map%local_id(self%gid(c)) > 0) cycle
        if (any(g == self%gid(c))) cycle
        g = [g, self%gid(c)]
      end do
    end do
  end function extra_ghosts

  !> The connections' local ids in the pressure map (after it is built).
  subroutine set_local(self, pmap)
    class(well_links_t), intent(inout) :: self
    type(index_map_t), intent(in) :: pmap
    integer :: c
    do c = 1, size(self%gid)
      self%elem(c) = pmap%local_id(self%gid(c))
    end do
  end subroutine set_local

  !> Element pairs (local ids) coupled in the mass rows: every two
  !> connections of a segment well with a row here.
  function pairs(self) result(pr)
    class(well_links_t), intent(in) :: self
    integer(ip), allocatable :: pr(:,:)
    integer :: k, c, d, n
    n = 0
    allocate(pr(2, sum([((self%first(k + 1) - self%first(k))**2, k = 1, size(self%along))])))
    do k = 1, size(self%along)
      if (.not. self%along(k)) cycle
      do c = self%first(k), self%first(k + 1) - 1
        if (.not. self%mine(c)) cycle
        do d = self%first(k), self%first(k + 1) - 1
          n = n + 1
          pr(:, n) = [self%elem(c), self%elem(d)]
        end do
      end do
    end do
    pr = pr(:, 1:n)
  end function pairs

  !> Start a step ending at time t [s] of size dt: the wells' rates (zero in
  !> a step of size 0) and the connection indices from the apertures a
  !> (local elements) and viscosity mu. Collective.
  subroutine begin_step(self, wells, aperture, mu, t, dt)
    class(well_links_t), intent(inout) :: self
    type(well_config_t), intent(in) :: wells(:)
    real(rp), intent(in) :: aperture(:), mu, t, dt
    real(rp) :: jp(size(self%gid))
    logical :: peaceman(size(self%gid))
    integer :: k, c
    jp = 0.0_rp
    do k = 1, size(wells)
      self%q(k) = merge(wells(k)%rate_at(t), 0.0_rp, dt > 0.0_rp)
      do c = self%first(k), self%first(k + 1) - 1
        peaceman(c) = self%along(k) .and. .not. self%index(k) > 0.0_rp
        if (.not. peaceman(c)) self%j(c) = merge(self%index(k), 1.0_rp, self%along(k))
        if (peaceman(c) .and. self%mine(c)) &
          jp(c) = 2.0_rp * pi * aperture(self%elem(c))**3 / (12.0_rp * mu * log(self%r_e(c) / self%radius(k)))
      end do
    end do
    call self%comm%sum_all(jp)
    where (peaceman) self%j = jp
  end subroutine begin_step

  !> The wells' terms of the mass rows (in volumes over the step, so -dt q_c
  !> in the residual r): rhs(e) = -r gets dt q_c and the Jacobian jpp the
  !> derivatives of -dt q_c, on the rows whose free(e) is true (a held or
  !> prescribed row takes none). p: pressures of the local elements, the
  !> connections' ghosts current.
  subroutine add_mass_terms(self, p, dt, free, jpp, rhs)
    class(well_links_t), intent(in) :: self
    real(rp), intent(in) :: p(:), dt
    logical, intent(in) :: free(:)
    type(csr_matrix_t), intent(inout) :: jpp
    real(rp), intent(inout) :: rhs(:)
    real(rp) :: q(size(self%gid)), sj
    integer :: k, c, d
    q = self%rates(p)
    do k = 1, size(self%along)
      sj = sum(self%j(self%first(k):self%first(k + 1) - 1))
      do c = self%first(k), self%first(k + 1) - 1
        if (.not. self%mine(c)) cycle
        if (.not. free(self%elem(c))) cycle
        rhs(self%elem(c)) = rhs(self%elem(c)) + dt * q(c)
        if (.not. self%along(k)) cycle
        call jpp%add_value(self%elem(c), self%elem(c), dt * self%j(c))
        do d = self%first(k), self%first(k + 1) - 1
          call jpp%add_value(self%elem(c), self%elem(d), -dt * self%j(c) * self%j(d) / sj)
        end do
      end do
    end do
  end subroutine add_mass_terms

  !> The connections' rates [m^3/s] at pressures p (local elements, the
  !> connections' ghosts current), on the connections owned here (0 on the
  !> others). Local.
  function rates(self, p) result(q)
    class(well_links_t), intent(in) :: self
    real(rp), intent(in) :: p(:)
    real(rp) :: q(size(self%gid))
    real(rp) :: sj, pbar
    integer :: k, c
    q = 0.0_rp
    do k = 1, size(self%along)
      if (.not. any(self%mine(self%first(k):self%first(k + 1) - 1))) cycle
      if (.not. self%along(k)) then
        c = self%first(k)
        q(c) = self%q(k)
        cycle
      end if
      associate (cs => self%first(k), ce => self%first(k + 1) - 1)
        sj = sum(self%j(cs:ce))
        pbar = sum(self%j(cs:ce) * p(self%elem(cs:ce))) / sj
        do c = cs, ce
          if (self%mine(c)) q(c) = self%j(c) * self%q(k) / sj + self%j(c) * (pbar - p(self%elem(c)))
        end do
      end associate
    end do
  end function rates

  !> Every well's bottom-hole pressure [Pa]: p_w of a segment well, the
  !> pressure of its element for a well at a point. Collective.
  function bottom_hole(self, p) result(pw)
    class(well_links_t), intent(in) :: self
    real(rp), intent(in) :: p(:)
    real(rp) :: pw(size(self%along))
    integer :: k, c
    pw = 0.0_rp
    do k = 1, size(self%along)
      do c = self%first(k), self%first(k + 1) - 1
        if (.not. self%mine(c)) cycle
        if (self%along(k)) then
          pw(k) = pw(k) + self%j(c) * p(self%elem(c))
        else
          pw(k) = p(self%elem(c))
        end if
      end do
    end do
    call self%comm%sum_all(pw)
    do k = 1, size(self%along)
      if (self%along(k)) pw(k) = (pw(k) + self%q(k)) / sum(self%j(self%first(k):self%first(k + 1) - 1))
    end do
  end function bottom_hole

  integer function n_conn(self, k)
    class(well_links_t), intent(in) :: self
    integer, intent(in) :: k
    n_conn = self%first(k + 1) - self%first(k)
  end function n_conn

  subroutine free(self)
    class(well_links_t), intent(inout) :: self
    if (allocated(self%first)) deallocate(self%first, self%along, self%radius, self%index, self%q)
    if (allocated(self%gid)) deallocate(self%gid, self%fault)
    if (allocated(self%elem)) deallocate(self%elem, self%mine, self%centre, self%r_e, self%j)
  end subroutine free

  ! ---- helpers ---------------------------------------------------------------

  !> Global id of the owned element whose centre is nearest to x over all
  !> ranks (ties: the lowest original id). Collective.
  integer(gp) function nearest_element(mesh, x) result(g)
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: x(3)
    real(rp) :: best, d2, gbest
    integer(gp) :: bid, gid
    integer(ip) :: e, chosen
    type(parallel_comm_t) :: comm
    comm = mesh%comm
    best = huge(1.0_rp)
    bid = huge(1_gp)
    chosen = 0
    do e = 1, mesh%iface_map%n_owned
      d2 = sum((centre_of(mesh, e) - x)**2)
      if (d2 < best .or. (d2 == best .and. mesh%iface_orig(e) < bid)) then
        best = d2
        bid = mesh%iface_orig(e)
        chosen = e
      end if
    end do
    gbest = comm%min(best)
    gid = -comm%max(-merge(bid, huge(1_gp), best == gbest))
    g = 0
    if (chosen > 0 .and. best == gbest .and. bid == gid) g = mesh%iface_map%global_id(chosen)
    g = comm%sum(g)
  end function nearest_element

  !> Per fault, the global id of the element the segment seg (start, end)
  !> crosses, 0 where it crosses none (ties: the lowest original id).
  !> Collective.
  function crossed(mesh, seg, nf) result(g)
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: seg(6)
    integer, intent(in) :: nf
    integer(gp) :: g(nf), bid(nf), gbid(nf)
    integer(ip) :: e, chosen(nf)
    integer :: f
    type(parallel_comm_t) :: comm
    comm = mesh%comm
    bid = huge(1_gp)
    chosen = 0
    do e = 1, mesh%iface_map%n_owned
      f = mesh%iface_fault(e)
      if (mesh%iface_orig(e) >= bid(f)) cycle
      if (.not. hits(mesh%coords(:, mesh%iface_nodes(:, 1, e)), seg)) cycle
      bid(f) = mesh%iface_orig(e)
      chosen(f) = e
    end do
    g = 0
    do f = 1, nf
      gbid(f) = -comm%max(-bid(f))
      if (chosen(f) > 0 .and. bid(f) == gbid(f)) g(f) = mesh%iface_map%global_id(chosen(f))
    end do
    call comm%sum_all(g)
  end function crossed

  !> Does the segment seg (start, end) meet the quadrilateral x(3, 4) (its
  !> two triangles 1-2-3 and 1-3-4, edges and corners included)?
  logical function hits(x, seg)
    real(rp), intent(in) :: x(3, 4), seg(6)
    hits = hits_triangle(x(:, 1), x(:, 2), x(:, 3), seg) .or. hits_triangle(x(:, 1), x(:, 3), x(:, 4), seg)
  end function hits

  !> Segment against triangle (Moeller and Trumbore, J. Graphics Tools 2
  !> (1997) 21), with a relative tolerance on the edges; a segment in the
  !> triangle's plane does not cross it.
  logical function hits_triangle(v0, v1, v2, seg)
    real(rp), intent(in) :: v0(3), v1(3), v2(3), seg(6)
    real(rp), parameter :: tol = 1.0e-10_rp
    real(rp) :: d(3), e1(3), e2(3), pv(3), tv(3), qv(3), det, u, v, s
    d = seg(4:6) - seg(1:3)
    e1 = v1 - v0
    e2 = v2 - v0
    pv = cross(d, e2)
    det = dot_product(e1, pv)
    hits_triangle = .false.
    if (abs(det) <= tol * norm2(d) * norm2(e1) * norm2(e2)) return
    tv = seg(1:3) - v0
    u = dot_product(tv, pv) / det
    qv = cross(tv, e1)
    v = dot_product(d, qv) / det
    s = dot_product(e2, qv) / det
    hits_triangle = u >= -tol .and. v >= -tol .and. u + v <= 1.0_rp + tol .and. s >= -tol .and. s <= 1.0_rp + tol
  end function hits_triangle

  pure function cross(a, b) result(c)
    real(rp), intent(in) :: a(3), b(3)
    real(rp) :: c(3)
    c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
  end function cross

  function centre_of(mesh, e) result(c)
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: e
    real(rp) :: c(3)
    c = sum(mesh%coords(:, mesh%iface_nodes(:, 1, e)), dim=2) / 4.0_rp
  end function centre_of

  !> Peaceman's equivalent radius 0.14 sqrt(dx^2 + dy^2) of element e, dx and
  !> dy its mid-lines (the nodes go round the quadrilateral).
  real(rp) function equivalent_radius(mesh, e) result(r)
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: e
    real(rp) :: x(3, 4), dx, dy
    x = mesh%coords(:, mesh%iface_nodes(:, 1, e))
    dx = norm2((x(:, 2) + x(:, 3)) - (x(:, 1) + x(:, 4))) / 2.0_rp
    dy = norm2((x(:, 3) + x(:, 4)) - (x(:, 1) + x(:, 2))) / 2.0_rp
    r = 0.14_rp * sqrt(dx**2 + dy**2)
  end function equivalent_radius

  function coords(x) result(s)
    real(rp), intent(in) :: x(3)
    character(len=80) :: s
    s = rtoa(x(1))//', '//rtoa(x(2))//', '//rtoa(x(3))
  end function coords
end module fracture_wells
