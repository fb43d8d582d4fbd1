!> Lowest-order Raviart-Thomas (RT0) elements on hexahedra, for the Darcy
!> flux q of three-field Biot poromechanics.
!>
!> Unknown: one per face, the total normal flux through the face [m^3/s].
!> The basis function psi_f of face f has unit flux through f and zero flux
!> through the five other faces, so a flux field is q(x) = sum_f q_f psi_f(x)
!> and psi_f is measured in [1/m^2] (velocity per unit flux).
!>
!> Reference cell [-1,1]^3, local faces in the order of mesh.f90's
!> hex_face_nodes: 1 xi=-1, 2 xi=+1, 3 eta=-1, 4 eta=+1, 5 zeta=-1, 6 zeta=+1.
!> With d the axis of face f and s = -1 (odd f) or +1 (even f), the reference
!> basis is psi_hat_f = (s + xi_d)/8 e_d: it vanishes on the opposite face,
!> is tangential to the four others, and its outward normal component on f is
!> 1/4, i.e. a flux of 1 through the reference face of area 4; div psi_hat_f = 1/8.
!>
!> Physical cells use the contravariant Piola map with J = dx/dxi of the
!> trilinear (Q1) geometry: psi = J psi_hat / det J, div psi = div_hat psi_hat / det J.
!> It preserves normal fluxes face by face, so every routine here returns the
!> LOCAL basis with the OUTWARD orientation of each local face.
!>
!> Orientation (local -> global): the global unknown of face f = cell_faces(lf, c)
!> is the flux in the direction of the global face normal (the normal of
!> face_nodes(:, f) as seen from face_cells(1, f)). Hence
!>     global basis of f restricted to cell c = cell_face_sign(lf, c) * local basis lf,
!> with cell_face_sign = +1 when the global normal points out of c. rt0_orient
!> applies these signs to a local vector (d_i -> s_i d_i) or matrix
!> (m_ij -> s_i s_j m_ij) before it is assembled into the global system.
module hex_rt0
  use, intrinsic :: iso_fortran_env, only: error_unit
  use kinds, only: rp, ip, msg_len
  use error_status, only: error_status_t
  use hex_q1, only: hex_shape
  use quadrature, only: gauss_hex
  implicit none
  private

  public :: rt0_ref_values, rt0_values, rt0_cell_mass, rt0_cell_divergence, rt0_orient

  !> Gauss points per direction of the cell mass matrix. The integrand
  !> psi_i . kinv psi_j det J = psi_hat_i^T J^T kinv J psi_hat_j / det J is a
  !> polynomial of degree 2 per direction on a parallelepiped (J constant), so
  !> 2x2x2 is exact there. On a non-affine cell it is rational and no Gauss
  !> rule is exact; 2x2x2 is the standard rule of Q1/RT0 hexahedra, gives a
  !> symmetric positive definite matrix while det J > 0 at the points, and its
  !> error falls like the square of the cell's distortion from a parallelepiped
  !> (measured against 4x4x4 on a unit cell with a full kinv and every corner
  !> moved by up to d in each coordinate: relative error 8.6e-3 at d = 0.2,
  !> 1.1e-3 at 0.1, 4.3e-5 at 0.025). Mesh refinement makes cells tend to
  !> parallelepipeds (d ~ h), so this O(h^2) error stays below the O(h) RT0
  !> error; 3x3x3 (3.4 times the work) would only pay on very distorted cells.
  integer(ip), parameter :: n_gauss = 2

  !> Local faces on which rt0_orient acts.
  integer, parameter :: n_faces = 6

  interface rt0_orient
    module procedure orient_vector, orient_matrix
  end interface rt0_orient

contains

  !> Reference basis at xi in [-1,1]^3: v(3,6) the vectors psi_hat_f (outward
  !> orientation, unit flux through face f), divv(6) their divergences.
  pure subroutine rt0_ref_values(xi, v, divv)
    real(rp), intent(in) :: xi(3)
    real(rp), intent(out) :: v(3, n_faces), divv(n_faces)
    integer :: f, d
    real(rp) :: s
    v = 0.0_rp
    do f = 1, n_faces
      d = (f + 1) / 2
      s = merge(1.0_rp, -1.0_rp, mod(f, 2) == 0)
      v(d, f) = 0.125_rp * (s + xi(d))
    end do
    divv = 0.125_rp
  end subroutine rt0_ref_values

  !> Physical basis at the reference point xi of the cell with node coordinates
  !> x(3,8) [m] (node order of mesh.f90): v(3,6) the vectors psi_f [1/m^2] with
  !> the outward orientation of each local face, divv(6) their divergences
  !> [1/m^3], det = det(dx/dxi) [m^3 / reference volume]. det <= 0 means an
  !> inverted or degenerate cell: v and divv are then returned as zero and the
  !> caller must treat the cell as an error.
  pure subroutine rt0_values(x, xi, v, divv, det)
    real(rp), intent(in) :: x(3, 8), xi(3)
    real(rp), intent(out) :: v(3, n_faces), divv(n_faces), det
    real(rp) :: n(8), dn(3, 8), jac(3, 3), vh(3, n_faces), divh(n_faces)
    call hex_shape(xi, n, dn)
    jac = matmul(x, transpose(dn))     ! jac(i, r) = d x_i / d xi_r
    det = jac(1,1)*(jac(2,2)*jac(3,3) - jac(3,2)*jac(2,3)) &
        - jac(1,2)*(jac(2,1)*jac(3,3) - jac(3,1)*jac(2,3)) &
        + jac(1,3)*(jac(2,1)*jac(3,2) - jac(3,1)*jac(2,2))
    if (det <= 0.0_rp) then
      v = 0.0_rp
      divv = 0.0_rp
      return
    end if
    call rt0_ref_values(xi, vh, divh)
    v = matmul(jac, vh) / det
    divv = divh / det
  end subroutine rt0_values

  !> Local mass matrix m(i,j) = int_cell psi_i . kinv psi_j dx [Pa s / m^3] of
  !> the cell x(3,8) [m], with the constant tensor kinv(3,3) = mu k^-1
  !> [Pa s / m^2] (symmetric positive definite, so m is too). Local faces,
  !> outward orientation (see rt0_orient). 2x2x2 Gauss (see n_gauss).
  !> A non-positive Jacobian at a Gauss point is reported in status and m is
  !> zero; without status it is taken as a programming error (meshes pass
  !> mesh_t%check first) and stops.
  subroutine rt0_cell_mass(x, kinv, m, status)
    real(rp), intent(in) :: x(3, 8), kinv(3, 3)
    real(rp), intent(out) :: m(n_faces, n_faces)
    type(error_status_t), intent(inout), optional :: status
    real(rp) :: xq(3, n_gauss**3), wq(n_gauss**3), v(3, n_faces), divv(n_faces), det
    integer :: q
    call gauss_hex(n_gauss, xq, wq)
    m = 0.0_rp
    do q = 1, size(wq)
      call rt0_values(x, xq(:, q), v, divv, det)
      if (det <= 0.0_rp) then
        m = 0.0_rp
        call bad_cell('rt0_cell_mass', xq(:, q), det, status)
        return
      end if
      m = m + (wq(q) * det) * matmul(transpose(v), matmul(kinv, v))
    end do
    ! exact symmetry, whatever the rounding of the products above
    m = 0.5_rp * (m + transpose(m))
  end subroutine rt0_cell_mass

  !> Divergence integrals d(i) = int_cell div psi_i dx of the cell x(3,8) [m]
  !> (dimensionless; +1 for every local face with the outward orientation,
  !> since the flux of psi_i out of the cell is 1). Errors as rt0_cell_mass.
  subroutine rt0_cell_divergence(x, d, status)
    real(rp), intent(in) :: x(3, 8)
    real(rp), intent(out) :: d(n_faces)
    type(error_status_t), intent(inout), optional :: status
    real(rp) :: xq(3, n_gauss**3), wq(n_gauss**3), v(3, n_faces), divv(n_faces), det
    integer :: q
    call gauss_hex(n_gauss, xq, wq)
    d = 0.0_rp
    do q = 1, size(wq)
      call rt0_values(x, xq(:, q), v, divv, det)
      if (det <= 0.0_rp) then
        d = 0.0_rp
        call bad_cell('rt0_cell_divergence', xq(:, q), det, status)
        return
      end if
      d = d + (wq(q) * det) * divv
    end do
  end subroutine rt0_cell_divergence

  !> Local (outward) to global face orientation of a cell vector:
  !> d(i) <- sgn(i) d(i), with sgn = cell_face_sign(:, c).
  pure subroutine orient_vector(sgn, d)
    integer(ip), intent(in) :: sgn(n_faces)
    real(rp), intent(inout) :: d(n_faces)
    d = real(sgn, rp) * d
  end subroutine orient_vector

  !> Local (outward) to global face orientation of a cell matrix:
  !> m(i,j) <- sgn(i) sgn(j) m(i,j), with sgn = cell_face_sign(:, c).
  pure subroutine orient_matrix(sgn, m)
    integer(ip), intent(in) :: sgn(n_faces)
    real(rp), intent(inout) :: m(n_faces, n_faces)
    integer :: j
    do j = 1, n_faces
      m(:, j) = real(sgn * sgn(j), rp) * m(:, j)
    end do
  end subroutine orient_matrix

  subroutine bad_cell(where, xi, det, status)
    character(len=*), intent(in) :: where
    real(rp), intent(in) :: xi(3), det
    type(error_status_t), intent(inout), optional :: status
    character(len=msg_len) :: msg
    write(msg, '(a,a,3f8.4,a,es10.3,a)') where, ': non-positive Jacobian at xi = (', xi, '), det = ', det, &
      ' (inverted or degenerate cell)'
    if (.not. present(status)) then
      write(error_unit, '(a)') trim(msg)
      error stop 'hex_rt0: non-positive Jacobian (inverted or degenerate cell)'
    end if
    call status%set(msg)
  end subroutine bad_cell
end module hex_rt0
