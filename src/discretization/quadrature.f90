!> Gauss-Legendre rules on [-1,1] and their tensor products on the reference
!> square and cube.
module quadrature
  use kinds, only: rp, ip
  implicit none
  private

  public :: gauss_1d, gauss_quad, gauss_hex

contains

  !> n-point Gauss-Legendre rule (n = 1..4): points x(n), weights w(n).
  subroutine gauss_1d(n, x, w)
    integer(ip), intent(in) :: n
    real(rp), intent(out) :: x(n), w(n)
    real(rp), parameter :: a2 = 0.577350269189625764509148780502_rp
    real(rp), parameter :: a3 = 0.774596669241483377035853079956_rp
    real(rp), parameter :: a4 = 0.339981043584856264802665759103_rp, b4 = 0.861136311594052575223946488893_rp
    real(rp), parameter :: wa4 = 0.652145154862546142626936050778_rp, wb4 = 0.347854845137453857373063949222_rp
    select case (n)
    case (1)
      x = [0.0_rp]; w = [2.0_rp]
    case (2)
      x = [-a2, a2]; w = [1.0_rp, 1.0_rp]
    case (3)
      x = [-a3, 0.0_rp, a3]; w = [5.0_rp, 8.0_rp, 5.0_rp] / 9.0_rp
    case (4)
      x = [-b4, -a4, a4, b4]; w = [wb4, wa4, wa4, wb4]
    case default
      error stop 'gauss_1d: only 1 to 4 points'
    end select
  end subroutine gauss_1d

  !> n x n rule on [-1,1]^2: xi(2, n*n), w(n*n).
  subroutine gauss_quad(n, xi, w)
    integer(ip), intent(in) :: n
    real(rp), intent(out) :: xi(2, n*n), w(n*n)
    real(rp) :: x(n), wx(n)
    integer(ip) :: i, j, k
    call gauss_1d(n, x, wx)
    k = 0
    do j = 1, n
      do i = 1, n
        k = k + 1
        xi(:, k) = [x(i), x(j)]
        w(k) = wx(i) * wx(j)
      end do
    end do
  end subroutine gauss_quad

  !> n x n x n rule on [-1,1]^3: xi(3, n**3), w(n**3).
  subroutine gauss_hex(n, xi, w)
    integer(ip), intent(in) :: n
    real(rp), intent(out) :: xi(3, n**3), w(n**3)
    real(rp) :: x(n), wx(n)
    integer(ip) :: i, j, k, q
    call gauss_1d(n, x, wx)
    q = 0
    do k = 1, n
      do j = 1, n
        do i = 1, n
          q = q + 1
          xi(:, q) = [x(i), x(j), x(k)]
          w(q) = wx(i) * wx(j) * wx(k)
        end do
      end do
    end do
  end subroutine gauss_hex
end module quadrature
