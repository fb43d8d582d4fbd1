!> Three-field Biot poromechanics: displacement u (Q1, 3 per node), Darcy flux
!> q (RT0, 1 per face: total flux along the global face normal) and pressure
!> p (P0, 1 per cell), implicit Euler with gamma = dt. The block system of a
!> time step (the seed's form, third row multiplied by gamma):
!>
!>     [ K    0      -Q ] [u]   [ f                                     ]
!>     [ 0    A      -B ] [q] = [ -(p_bar on pressure faces)            ]
!>     [ Q^T  g B^T   P ] [p]   [ g*source + Q^T u_old + P p_old        ]
!>
!> K: elasticity (from elasticity_t), Q(u_ai, c) = b int_c dN_a/dx_i,
!> A(f, f') = int psi_f . mu k^-1 psi_f', B(f, c) = int_c div psi_f (= +-1),
!> P(c, c) = |c| / M, g = gamma = dt (0 for the undrained step); a
!> pressure-controlled source (index I, pressure p_w) has source = I (p_w -
!> p): g I |c| joins P(c, c) and g I |c| p_w the right-hand side.
!> Prescribed displacements and fluxes are eliminated symmetrically (their
!> known values go to the right-hand side; their rows get a scaled identity);
!> boundary faces without a pressure or flux condition are impermeable.
!> Blocks are numbered 1 = u, 2 = q, 3 = p.
module poromechanics
  use kinds, only: rp, ip, gp, msg_len
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use index_map, only: index_map_t
  use csr_matrix, only: csr_matrix_t
  use block_matrix, only: block_matrix_t
  use dist_mesh, only: dist_mesh_t
  use dof_map, only: dof_map_t
  use sparsity, only: element_pattern
  use quadrature, only: gauss_hex
  use hex_q1, only: hex_gradients
  use elasticity, only: elasticity_t
  use poro_media, only: poro_media_t, cell_coupling, cell_darcy, flow_patterns
  use material_config, only: material_config_t
  use boundary_config, only: boundary_config_t
  use source_config, only: source_config_t
  implicit none
  private

  public :: poromechanics_t, iu, iq, ipr

  integer, parameter :: iu = 1, iq = 2, ipr = 3

  !> The medium's data and kernels (poro_media_t: materials, flux boundary
  !> data, stabilization weights) and the Biot system of a step.
  type, extends(poro_media_t) :: poromechanics_t
    type(elasticity_t) :: mech
    type(dof_map_t) :: qd, pd                 !< flux (faces) and pressure (cells) dofs
    type(block_matrix_t) :: sys
    real(rp), allocatable :: rhs(:)           !< block vector
    real(rp), allocatable :: x(:), x_old(:)   !< state at the new and the previous time (block vectors)
    !> The matrix is the same at every step but for its (p, q) block, dt B,
    !> and (adaptive stabilization) its (p, p) block: assembled once
    !> (matrix_ready), then only the (p, q) block is scaled (from pq_unit,
    !> B's values), the (p, p) block made again when dt changes, and the
    !> right-hand side made again
    logical :: matrix_ready = .false.
    real(rp), allocatable :: pq_unit(:)
  contains
    procedure :: init
    procedure :: assemble
    procedure :: fixed_stress_schur
    procedure :: algebraic_schur
    procedure :: free
  end type poromechanics_t

contains

  !> Dofs, block patterns, materials and boundary data. stab_beta > 0 turns
  !> on the pressure-jump stabilization with that factor (0: off);
  !> stab_adaptive sizes it by the closeness of each step to the undrained
  !> incompressible limit (else it has that limit's size at every step).
  !> Collective.
  subroutine init(self, mesh, mats, bcs, srcs, stab_beta, stab_adaptive, status)
    class(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in), target :: mesh
    type(material_config_t), intent(in) :: mats(:)
    type(boundary_config_t), intent(in) :: bcs(:)
    type(source_config_t), intent(in) :: srcs(:)
    real(rp), intent(in) :: stab_beta
    logical, intent(in) :: stab_adaptive
    type(error_status_t), intent(inout) :: status
    integer(ip), allocatable :: row_ptr(:), col(:)

    call self%free()
    call self%mech%init(mesh, mats, bcs, status)
    if (.not. status%ok()) return
    call self%init_media(mesh, mats, bcs, srcs, stab_beta, stab_adaptive, self%mech%box_tol, 'biot', status)
    if (.not. status%ok()) return

    call self%qd%init('flux', mesh%face_map, 1_ip)
    call self%pd%init('pressure', mesh%cell_map, 1_ip)
    call self%sys%init([self%mech%u%n_owned(), self%qd%n_owned(), self%pd%n_owned()])
    call element_pattern(mesh%node_map%n_owned, mesh%cell_nodes, mesh%cell_nodes, 3_ip, 3_ip, row_ptr, col)
    call self%sys%set_pattern(iu, iu, self%mech%u%map, self%mech%u%map, row_ptr, col)
    call flow_patterns(mesh, self%sys, [iu, iq, ipr], self%mech%u%map, self%qd%map, self%pd%map)
    n_check: block
      integer(ip) :: nb
      nb = self%sys%offset(4)
      allocate(self%rhs(nb), self%x(nb), self%x_old(nb))
    end block n_check
    self%x = 0.0_rp
    self%x_old = 0.0_rp
  end subroutine init



  !> The (p, p) block: storage |c| / M, the pressure-controlled sources'
  !> dt I |c| and the stabilization J with the weights of jump_w (all of
  !> the step size jump_dt). Collective.
  subroutine pressure_block(self, mesh)
    type(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip) :: c
    associate (pp => self%sys%a(ipr, ipr))
      pp%val = 0.0_rp
      do c = 1, mesh%cell_map%n_owned
        call self%storage_row(mesh, c, self%jump_dt, pp)
      end do
      call pp%finalize_assembly()
    end associate
  end subroutine pressure_block




  !> Assemble the block system and right-hand side of the step to the new
  !> time t_new with gamma = dt (0: undrained step), from the state x_old.
  !> Boundary histories are evaluated at t_new. Collective.
  subroutine assemble(self, mesh, t_new, dt, status)
    class(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: t_new, dt
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: u_old(:), q_loc(:), rhs_u(:), p_old(:)
    real(rp) :: xe(3, 8), qe(24), ae(6, 6), be(6), b
    integer(ip) :: c, a, j, dofs(24), faces(6), r, nu, nq, i, f, u0, u1, q0, q1, p0, p1
    logical :: matrix, weights, moved, fluxed

    ! the matrix once (it does not change but for dt B and the stabilization
    ! of an adaptive size); the right-hand side always
    matrix = .not. self%matrix_ready
    if (matrix) call self%sys%zero()
    weights = self%jump_factor(dt)
    call self%sys%block_range(iu, u0, u1)
    call self%sys%block_range(iq, q0, q1)
    call self%sys%block_range(ipr, p0, p1)
    ! mechanics: K and f with the displacement conditions
    call self%mech%set_time(t_new)
    allocate(rhs_u(u1 - u0 + 1))
    call self%mech%assemble_into(mesh, 1.0_rp, self%sys%a(iu, iu), rhs_u, rhs_only=.not. matrix)
    self%rhs = 0.0_rp
    self%rhs(u0:u1) = rhs_u
    ! previous displacement with ghosts (for the eliminated columns of Q^T)
    nu = self%mech%u%n_local()
    allocate(u_old(nu))
    u_old = 0.0_rp
    u_old(1:self%mech%u%n_owned()) = self%x_old(u0:u1)
    call self%mech%u%map%import(u_old)
    nq = self%qd%n_local()
    allocate(q_loc(nq))
    q_loc = 0.0_rp
    allocate(p_old(self%pd%n_local()))
    p_old = 0.0_rp
    p_old(1:self%pd%n_owned()) = self%x_old(p0:p1)
    call self%pd%map%import(p_old)

    do c = 1, mesh%cell_map%n_owned
      xe = mesh%coords(:, mesh%cell_nodes(:, c))
      r = mesh%cell_region(c)
      b = self%biot(r)
      do a = 1, 8
        dofs(3*a-2:3*a) = self%mech%u%dof(mesh%cell_nodes(a, c), [1_ip, 2_ip, 3_ip])
      end do
      ! Q_e = b int grad N (for the matrix, or the columns of the known
      ! displacements that change over the step)
      moved = .false.
      do j = 1, 24
        if (self%mech%fixed(dofs(j))) moved = moved .or. self%mech%prescribed_value(dofs(j)) /= u_old(dofs(j))
      end do
      if (matrix .or. moved) then
        call cell_coupling(xe, b, qe)
        do j = 1, 24
          if (self%mech%fixed(dofs(j))) then
            ! known displacement: Q^T column to the right-hand side (its change over the step)
            if (moved) self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) - qe(j) * (self%mech%prescribed_value(dofs(j)) - &
                                                                        u_old(dofs(j)))
          else if (matrix) then
            call self%sys%a(iu, ipr)%add_value(dofs(j), c, -qe(j))
            call self%sys%a(ipr, iu)%add_value(c, dofs(j), qe(j))
          end if
        end do
      end if
      ! Darcy: A_e and B_e in the global face orientation (for the matrix,
      ! or the columns of nonzero prescribed fluxes)
      faces = mesh%cell_faces(:, c)
      fluxed = .false.
      do j = 1, 6
        if (self%q_fixed(faces(j))) fluxed = fluxed .or. flux_value(faces(j)) /= 0.0_rp
      end do
      if (matrix .or. fluxed) then
        call cell_darcy(xe, self%kinv(:, :, r), mesh%cell_face_sign(:, c), ae, be, status)
        if (.not. status%ok()) return
      end if
      do j = 1, 6
        f = faces(j)
        if (self%q_fixed(f)) then
          if (.not. fluxed) cycle
          do i = 1, 6
            if (.not. self%q_fixed(faces(i))) q_loc(faces(i)) = q_loc(faces(i)) - ae(i, j) * flux_value(f)
          end do
          self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) - dt * be(j) * flux_value(f)
          cycle
        end if
        if (matrix) then
          do i = 1, 6
            if (.not. self%q_fixed(faces(i))) call self%sys%a(iq, iq)%add_value(faces(i), f, ae(i, j))
          end do
          call self%sys%a(iq, ipr)%add_value(f, c, -be(j))
          call self%sys%a(ipr, iq)%add_value(c, f, be(j))      ! B; dt B below
        end if
        if (self%p_face(f)) q_loc(f) = q_loc(f) - self%p_bc(f) * self%bcs(self%face_bc(f))%factor(t_new)
      end do
      ! sources; the pressure-jump stabilization on the pressure increment
      ! (the storage and J of the (p, p) block: pressure_block)
      self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) + dt * (self%src_rate(c) + self%src_jp(c)) * self%vol(c)
      do j = 1, 6
        f = faces(j)
        if (self%jump_w(f) == 0.0_rp) cycle
        i = mesh%face_cells(1, f)
        if (i == c) i = mesh%face_cells(2, f)
        self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) + self%jump_w(f) * (p_old(c) - p_old(i))
      end do
    end do
    if (matrix) then
      call self%sys%finalize_assembly()
      self%pq_unit = self%sys%a(ipr, iq)%val
      self%matrix_ready = .true.
    end if
    if (weights .or. matrix) call pressure_block(self, mesh)
    self%sys%a(ipr, iq)%val = dt * self%pq_unit
    ! pressure faces appear once (one cell), counted above only for owned cells
    call self%qd%map%export_add(q_loc)
    self%rhs(q0:q1) = q_loc(1:self%qd%n_owned())

    call prescribed_flux_rows(self, t_new, q0)
    call old_state_and_norms(self, mesh, u0, u1, p0, p1)
  contains
    !> Prescribed flux through local face f at t_new [m^3/s].
    real(rp) function flux_value(f)
      integer(ip), intent(in) :: f
      flux_value = self%prescribed_flux(f, t_new)
    end function flux_value
  end subroutine assemble


  !> Rows of prescribed fluxes: a scaled identity (the mean diagonal of the
  !> free rows of A) with the flux at t_new on the right-hand side.
  !> Collective.
  subroutine prescribed_flux_rows(self, t_new, q0)
    type(poromechanics_t), intent(inout) :: self
    real(rp), intent(in) :: t_new
    integer(ip), intent(in) :: q0
    real(rp) :: dsum, dcount
    integer(ip) :: f, k
    dsum = 0.0_rp
    dcount = 0.0_rp
    do f = 1, self%qd%n_owned()
      if (self%q_fixed(f)) cycle
      k = self%sys%a(iq, iq)%find(f, f)
      dsum = dsum + self%sys%a(iq, iq)%val(k)
      dcount = dcount + 1.0_rp
    end do
    dsum = self%qd%map%comm%sum(dsum)
    dcount = self%qd%map%comm%sum(dcount)
    self%a_scale = 1.0_rp
    if (dcount > 0.0_rp) self%a_scale = dsum / dcount
    do f = 1, self%qd%n_owned()
      if (.not. self%q_fixed(f)) cycle
      k = self%sys%a(iq, iq)%find(f, f)
      self%sys%a(iq, iq)%val(k) = self%a_scale
      self%rhs(q0 + f - 1) = self%a_scale * self%prescribed_flux(f, t_new)
    end do
  end subroutine prescribed_flux_rows

  !> The previous state's terms of the mass balance (Q^T u_old on the free
  !> columns, P p_old) and the row norms of A (for the scaled-Laplacian
  !> Schur approximation, ghosts imported). Collective.
  subroutine old_state_and_norms(self, mesh, u0, u1, p0, p1)
    type(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    integer(ip), intent(in) :: u0, u1, p0, p1
    real(rp), allocatable :: tmp(:)
    integer(ip) :: c, f
    allocate(tmp(p1 - p0 + 1))
    call self%sys%apply_block(ipr, iu, self%x_old(u0:u1), tmp)
    self%rhs(p0:p1) = self%rhs(p0:p1) + tmp
    do c = 1, mesh%cell_map%n_owned
      self%rhs(p0 + c - 1) = self%rhs(p0 + c - 1) + self%vol(c) * self%inv_m(mesh%cell_region(c)) * &
                             self%x_old(p0 + c - 1)
    end do
    self%a_norm = 0.0_rp
    do f = 1, self%qd%n_owned()
      associate (am => self%sys%a(iq, iq))
        self%a_norm(f) = norm2(am%val(am%row_ptr(f):am%row_ptr(f+1)-1))
      end associate
    end do
    call self%qd%map%import(self%a_norm)
  end subroutine old_state_and_norms

  !> The explicit approximation of the pressure Schur complement
  !>   S = P + S_K + dt S_A,  S_K = diag(b^2 |c| / K_dr) (fixed stress),
  !>   S_A = B^T diag(a)^-1 B with a_f = ||A(f,:)||_2 (scaled Laplacian),
  !> on the pattern of the pressure block. Call after assemble. Collective.
  subroutine fixed_stress_schur(self, mesh, dt, s)
    class(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: dt
    type(csr_matrix_t), intent(inout) :: s
    integer(ip) :: c, j, f, r, other
    real(rp) :: sgn_c, sgn_o
    associate (pp => self%sys%a(ipr, ipr))
      if (.not. allocated(s%val)) call s%init(pp%row_map, pp%col_map, pp%row_ptr, pp%col)
    end associate
    call s%zero()
    do c = 1, mesh%cell_map%n_owned
      r = mesh%cell_region(c)
      call s%add_value(c, c, self%vol(c) * (self%inv_m(r) + self%biot(r)**2 / self%kdr(r)))
      call self%add_jumps(mesh, c, s)
      if (dt <= 0.0_rp) cycle
      do j = 1, 6
        f = mesh%cell_faces(j, c)
        if (self%q_fixed(f)) cycle
        call s%add_value(c, c, dt / self%a_norm(f))
        other = mesh%face_cells(1, f)
        if (other == c) other = mesh%face_cells(2, f)
        if (other == 0 .or. mesh%face_on_boundary(f)) cycle
        sgn_c = real(mesh%cell_face_sign(j, c), rp)
        sgn_o = -sgn_c
        call s%add_value(c, other, dt * sgn_c * sgn_o / self%a_norm(f))
      end do
    end do
    call s%finalize_assembly()
  end subroutine fixed_stress_schur

  !> The pressure Schur complement approximated with the algebraic
  !> generalization of fixed stress (Ferronato, Franceschini, Janna,
  !> Castelletto and Tchelepi, J. Comput. Phys. 398 (2019)): S_K is replaced by
  !> Q^T diag(K)^-1 Q instead of the per-cell b^2 |c| / K_dr, so that it sees
  !> the actual stiffness and boundary conditions; S = P + J + Q^T diag(K)^-1 Q
  !> + dt S_A, on the pattern of cells sharing a node. Call after assemble.
  !> Collective.
  subroutine algebraic_schur(self, mesh, dt, s)
    class(poromechanics_t), intent(inout) :: self
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: dt
    type(csr_matrix_t), intent(inout) :: s
    integer(ip), allocatable :: node_cells(:,:), cnt(:), row_ptr(:), col(:)
    real(rp), allocatable :: qc(:,:), dk(:)
    real(rp) :: xe(3, 8), xi(3, 8), w(8), n(8), g(3, 8), det
    integer(ip) :: c, a, k, q, i, nd, c2, a2, j, f, other, r, u0, u1
    ! Q of every local cell, and the cells around each local node
    call gauss_hex(2_ip, xi, w)
    allocate(qc(24, mesh%n_cells), cnt(mesh%n_nodes))
    cnt = 0
    do c = 1, mesh%n_cells
      cnt(mesh%cell_nodes(:, c)) = cnt(mesh%cell_nodes(:, c)) + 1
    end do
    allocate(node_cells(maxval(cnt), mesh%n_nodes))
    node_cells = 0
    cnt = 0
    do c = 1, mesh%n_cells
      xe = mesh%coords(:, mesh%cell_nodes(:, c))
      qc(:, c) = 0.0_rp
      do q = 1, 8
        call hex_gradients(xe, xi(:, q), n, g, det)
        do a = 1, 8
          qc(3*a-2:3*a, c) = qc(3*a-2:3*a, c) + self%biot(mesh%cell_region(c)) * g(:, a) * det * w(q)
        end do
      end do
      do a = 1, 8
        nd = mesh%cell_nodes(a, c)
        cnt(nd) = cnt(nd) + 1
        node_cells(cnt(nd), nd) = c
      end do
    end do
    if (.not. allocated(s%val)) then
      call element_pattern(mesh%cell_map%n_owned, node_cells, node_cells, 1_ip, 1_ip, row_ptr, col)
      call s%init(self%pd%map, self%pd%map, row_ptr, col)
    end if
    ! diagonal of K on every local dof
    allocate(dk(self%mech%u%n_local()))
    dk = 1.0_rp
    call self%sys%block_range(iu, u0, u1)
    call self%sys%a(iu, iu)%diagonal(dk(1:u1 - u0 + 1))
    call self%mech%u%map%import(dk)
    call s%zero()
    do c = 1, mesh%cell_map%n_owned
      r = mesh%cell_region(c)
      call s%add_value(c, c, self%vol(c) * self%inv_m(r))
      do a = 1, 8
        nd = mesh%cell_nodes(a, c)
        do k = 1, cnt(nd)
          c2 = node_cells(k, nd)
          a2 = findloc(mesh%cell_nodes(:, c2), nd, dim=1)
          do i = 1, 3
            j = self%mech%u%dof(nd, i)
            if (self%mech%fixed(j)) cycle
            call s%add_value(c, c2, qc(3*(a-1)+i, c) * qc(3*(a2-1)+i, c2) / dk(j))
          end do
        end do
      end do
      call self%add_jumps(mesh, c, s)
      do j = 1, 6
        f = mesh%cell_faces(j, c)
        if (dt <= 0.0_rp .or. self%q_fixed(f)) cycle
        other = mesh%face_cells(1, f)
        if (other == c) other = mesh%face_cells(2, f)
        call s%add_value(c, c, dt / self%a_norm(f))
        if (other == 0 .or. mesh%face_on_boundary(f)) cycle
        call s%add_value(c, other, -dt / self%a_norm(f))
      end do
    end do
    call s%finalize_assembly()
  end subroutine algebraic_schur


  subroutine free(self)
    class(poromechanics_t), intent(inout) :: self
    call self%sys%free()
    call self%mech%free()
    call self%qd%free()
    call self%pd%free()
    if (allocated(self%rhs)) deallocate(self%rhs, self%x, self%x_old)
    call self%free_media()
    self%matrix_ready = .false.
  end subroutine free
end module poromechanics
