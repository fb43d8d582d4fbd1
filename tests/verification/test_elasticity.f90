!> Fields of the verification problems (a linear field for the patch test,
!> a manufactured solution and its body force).
module elasticity_test_fields
  use kinds, only: rp
  use vector_function, only: vector_function_t
  implicit none
  private
  public :: linear_field_t, mms_u_t, mms_f_t, pi

  real(rp), parameter :: pi = 3.14159265358979323846_rp

  type, extends(vector_function_t) :: linear_field_t
  contains
    procedure :: eval => linear_eval
  end type linear_field_t

  type, extends(vector_function_t) :: mms_u_t
  contains
    procedure :: eval => mms_u_eval
  end type mms_u_t

  type, extends(vector_function_t) :: mms_f_t
    real(rp) :: lambda = 0.0_rp, mu = 0.0_rp
  contains
    procedure :: eval => mms_f_eval
  end type mms_f_t

contains

  function linear_eval(self, x) result(v)
    class(linear_field_t), intent(in) :: self
    real(rp), intent(in) :: x(3)
    real(rp) :: v(3)
    v = 1.0e-3_rp * [0.1_rp + 2.0_rp*x(1) - 1.0_rp*x(2) + 0.5_rp*x(3), &
                     -0.2_rp + 0.3_rp*x(1) + 1.5_rp*x(2) - 0.7_rp*x(3), &
                     0.05_rp - 0.4_rp*x(1) + 0.8_rp*x(2) + 1.1_rp*x(3)]
  end function linear_eval

  function mms_u_eval(self, x) result(v)
    class(mms_u_t), intent(in) :: self
    real(rp), intent(in) :: x(3)
    real(rp) :: v(3)
    v = 1.0e-3_rp * sin(pi*x(1)) * sin(pi*x(2)) * sin(pi*x(3))
  end function mms_u_eval

  !> f = -div sigma(u) = -[(lambda + mu) grad div u + mu lap u].
  function mms_f_eval(self, x) result(v)
    class(mms_f_t), intent(in) :: self
    real(rp), intent(in) :: x(3)
    real(rp) :: v(3), s(3), c(3), phi, gdiv(3)
    s = sin(pi * x)
    c = cos(pi * x)
    phi = s(1) * s(2) * s(3)
    gdiv(1) = pi**2 * (-phi + c(1)*c(2)*s(3) + c(1)*s(2)*c(3))
    gdiv(2) = pi**2 * (c(1)*c(2)*s(3) - phi + s(1)*c(2)*c(3))
    gdiv(3) = pi**2 * (c(1)*s(2)*c(3) + s(1)*c(2)*c(3) - phi)
    v = -1.0e-3_rp * ((self%lambda + self%mu) * gdiv - 3.0_rp * pi**2 * self%mu * phi)
  end function mms_f_eval

end module elasticity_test_fields

!> Verification of Q1 elasticity:
!>  - patch test: a linear displacement field prescribed on the boundary of a
!>    mesh with perturbed interior nodes is reproduced exactly (1e-10), with
!>    the exact constant stress;
!>  - manufactured solution u_i = sin(pi x) sin(pi y) sin(pi z): the L2 error
!>    converges with observed order >= 1.9 over three refinements (H1 seminorm
!>    order reported, expected ~1);
!>  - MUMPS and FGMRES + BoomerAMG agree to the solver tolerance.
program test_elasticity
  use kinds, only: rp, ip
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use logger, only: logger_t
  use assertions, only: test_suite_t
  use mesh, only: mesh_t
  use box_mesh, only: build_box_mesh
  use partition, only: partition_cells
  use dist_mesh, only: dist_mesh_t
  use elasticity, only: elasticity_t, lame
  use material_config, only: material_config_t
  use boundary_config, only: boundary_config_t
  use vector_function, only: vector_function_t
  use precon, only: precon_t
  use precon_factory, only: precon_params_t, make_and_setup
  use linear_system, only: linear_system_t
  use linear_solver, only: linear_solver_t
  use krylov, only: solve_info_t
  use quadrature, only: gauss_hex
  use hex_q1, only: hex_gradients
  use dist_vector, only: pnorm2
  use elasticity_test_fields, only: linear_field_t, mms_u_t, mms_f_t, pi
  implicit none

  real(rp), parameter :: young = 2.0e10_rp, nu = 0.3_rp

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  real(rp) :: err_l2(3), err_h1(3), h(3), order
  integer :: k
  character(len=160) :: line

  call comm%init_world()
  call suite%init('elasticity_verification', comm)

  call patch_test()

  do k = 1, 3
    call mms_run(4 * 2**(k-1), err_l2(k), err_h1(k))
    h(k) = 1.0_rp / real(4 * 2**(k-1), rp)
    if (comm%is_root()) then
      write(line, '(a,i3,a,es11.4,a,es11.4)') '  mms n =', 4 * 2**(k-1), '  L2 error ', err_l2(k), '  H1 error ', err_h1(k)
      print '(a)', trim(line)
    end if
  end do
  do k = 2, 3
    order = log(err_l2(k-1) / err_l2(k)) / log(h(k-1) / h(k))
    write(line, '(a,i0,a,f5.2)') 'MMS L2 observed order, refinement ', k - 1, ': ', order
    call suite%assert_true(order >= 1.9_rp, trim(line)//' >= 1.9')
    order = log(err_h1(k-1) / err_h1(k)) / log(h(k-1) / h(k))
    write(line, '(a,i0,a,f5.2)') 'MMS H1 observed order, refinement ', k - 1, ': ', order
    call suite%assert_true(order >= 0.9_rp, trim(line)//' >= 0.9')
  end do

  call mumps_vs_amg()
  call suite%finish()

contains

  !> Unit cube with every side clamped to a prescribed field (values come
  !> from the dirichlet function of assemble).
  subroutine setup_problem(n, perturb, mesh, phys)
    integer, intent(in) :: n
    logical, intent(in) :: perturb
    type(dist_mesh_t), intent(inout) :: mesh
    type(elasticity_t), intent(inout) :: phys
    type(mesh_t) :: g
    integer(ip), allocatable :: part(:)
    type(error_status_t) :: st
    type(material_config_t) :: mats(1)
    type(boundary_config_t) :: bcs(6)
    character(len=4), parameter :: sides(6) = ['xmin', 'xmax', 'ymin', 'ymax', 'zmin', 'zmax']
    integer :: i
    real(rp) :: d(3)
    if (comm%is_root()) then
      call build_box_mesh(g, [integer(ip) :: n, n, n], [0.0_rp, 0.0_rp, 0.0_rp], [1.0_rp, 1.0_rp, 1.0_rp], &
                          [1.0_rp, 1.0_rp, 1.0_rp], st)
      if (perturb) then
        do i = 1, g%n_nodes
          if (any(g%coords(:, i) < 1.0e-12_rp) .or. any(g%coords(:, i) > 1.0_rp - 1.0e-12_rp)) cycle
          d = [sin(12.9898_rp * i), sin(78.233_rp * i), sin(37.719_rp * i)]
          g%coords(:, i) = g%coords(:, i) + 0.2_rp / n * d
        end do
      end if
      allocate(part(g%n_cells))
      call partition_cells(g, int(comm%size, ip), part, st)
    end if
    call mesh%build(comm, g, part, st)
    mats(1) = material_config_t('domain', young, nu, [0.0_rp, 0.0_rp, 0.0_rp])
    do i = 1, 6
      bcs(i)%set = sides(i)
      bcs(i)%type = 'displacement'
      bcs(i)%fixed = .true.
    end do
    call phys%init(mesh, mats, bcs, st)
    call suite%assert_true(st%ok(), 'problem set-up n = '//trim(itoa(n))//': '//trim(st%msg))
  end subroutine setup_problem

  !> Solve K x = f by method ('cg', 'fgmres' with BoomerAMG, or 'mumps')
  !> through the project's linear-solve path.
  subroutine solve(phys, method, rtol, x, info)
    type(elasticity_t), intent(inout), target :: phys
    character(len=*), intent(in) :: method
    real(rp), intent(in) :: rtol
    real(rp), intent(inout), target :: x(:)
    type(solve_info_t), intent(out) :: info
    type(precon_params_t) :: params
    class(precon_t), allocatable, target :: pc
    type(linear_solver_t) :: ls
    type(linear_system_t) :: sys
    type(error_status_t) :: st
    call ls%init(comm, method, rtol, 0.0_rp, 1000, 100, st)
    sys%a => phys%k
    sys%b => phys%rhs
    sys%x => x
    sys%symmetric = .true.
    if (.not. ls%is_direct()) then
      call make_and_setup('boomeramg', pc, phys%k, params, st)
      sys%m => pc
    end if
    x = 0.0_rp
    call ls%solve(sys, info)
    call ls%free()
    if (allocated(pc)) call pc%free()
  end subroutine solve

  subroutine patch_test()
    type(dist_mesh_t) :: mesh
    type(elasticity_t) :: phys
    type(linear_field_t) :: lin
    type(solve_info_t) :: info
    real(rp), allocatable :: x(:), u(:), stress(:,:)
    real(rp) :: err, ref, lam, mu, eps(3, 3), sig(3, 3), sexp(6), serr
    integer(ip) :: i, nn, c
    call setup_problem(4, .true., mesh, phys)
    call phys%assemble(mesh, 1.0_rp, dirichlet=lin)
    nn = mesh%node_map%n_owned
    allocate(x(phys%u%n_owned()), u(phys%u%n_local()), stress(6, mesh%cell_map%n_owned))
    call solve(phys, 'cg', 1.0e-14_rp, x, info)
    err = 0.0_rp
    ref = 0.0_rp
    do i = 1, nn
      err = max(err, maxval(abs(x(3*i-2:3*i) - lin%eval(mesh%coords(:, i)))))
      ref = max(ref, maxval(abs(lin%eval(mesh%coords(:, i)))))
    end do
    err = comm%max(err) / comm%max(ref)
    call suite%assert_true(err <= 1.0e-10_rp, 'patch test: nodal displacement relative error '// &
                           trim(rtoa(err))//' <= 1e-10 (distorted mesh, '//trim(itoa(info%iterations))//' CG its)')
    ! the exact stress is constant
    u(1:size(x)) = x
    call phys%u%map%import(u)
    call phys%cell_stress(mesh, u, stress)
    call lame(young, nu, lam, mu)
    eps = 1.0e-3_rp * reshape([2.0_rp, 0.3_rp, -0.4_rp, -1.0_rp, 1.5_rp, 0.8_rp, 0.5_rp, -0.7_rp, 1.1_rp], [3, 3])
    eps = 0.5_rp * (eps + transpose(eps))
    sig = 2.0_rp * mu * eps
    do i = 1, 3
      sig(i, i) = sig(i, i) + lam * (eps(1,1) + eps(2,2) + eps(3,3))
    end do
    sexp = [sig(1,1), sig(2,2), sig(3,3), sig(1,2), sig(2,3), sig(1,3)]
    serr = 0.0_rp
    do c = 1, mesh%cell_map%n_owned
      serr = max(serr, maxval(abs(stress(:, c) - sexp)))
    end do
    serr = comm%max(serr) / maxval(abs(sexp))
    call suite%assert_true(serr <= 1.0e-9_rp, 'patch test: cell stress relative error '//trim(rtoa(serr))// &
                           ' <= 1e-9')
    call phys%free()
    call mesh%free()
  end subroutine patch_test

  !> Solve the manufactured problem on an n^3 mesh; L2 and H1-seminorm errors
  !> (3x3x3 Gauss per cell), relative to the norms of the exact solution.
  subroutine mms_run(n, el2, eh1)
    integer, intent(in) :: n
    real(rp), intent(out) :: el2, eh1
    type(dist_mesh_t) :: mesh
    type(elasticity_t) :: phys
    type(mms_u_t) :: uex
    type(mms_f_t) :: f
    type(solve_info_t) :: info
    real(rp), allocatable :: x(:), u(:)
    real(rp) :: xi(3, 27), w(27), xe(3, 8), nsh(8), g(3, 8), det, ue(3, 8), xq(3), diff(3), gh(3, 3), ge(3, 3)
    real(rp) :: s(3), cs(3), n2, d2, h2, r2
    integer(ip) :: c, q, a
    call setup_problem(n, .false., mesh, phys)
    call lame(young, nu, f%lambda, f%mu)
    call phys%assemble(mesh, 1.0_rp, body=f, dirichlet=uex)
    allocate(x(phys%u%n_owned()), u(phys%u%n_local()))
    call solve(phys, 'cg', 1.0e-12_rp, x, info)
    call suite%assert_true(info%converged, 'MMS n = '//trim(itoa(n))//' solve converged '//trim(info%msg))
    u(1:size(x)) = x
    call phys%u%map%import(u)
    call gauss_hex(3_ip, xi, w)
    d2 = 0.0_rp; n2 = 0.0_rp; h2 = 0.0_rp; r2 = 0.0_rp
    do c = 1, mesh%cell_map%n_owned
      xe = mesh%coords(:, mesh%cell_nodes(:, c))
      do a = 1, 8
        ue(:, a) = u(phys%u%dof(mesh%cell_nodes(a, c), [1_ip, 2_ip, 3_ip]))
      end do
      do q = 1, 27
        call hex_gradients(xe, xi(:, q), nsh, g, det)
        xq = matmul(xe, nsh)
        diff = matmul(ue, nsh) - uex%eval(xq)
        d2 = d2 + dot_product(diff, diff) * det * w(q)
        n2 = n2 + sum(uex%eval(xq)**2) * det * w(q)
        s = sin(pi * xq)
        cs = cos(pi * xq)
        ! exact gradient: every component has grad phi
        ge(:, 1) = 1.0e-3_rp * pi * [cs(1)*s(2)*s(3), cs(1)*s(2)*s(3), cs(1)*s(2)*s(3)]
        ge(:, 2) = 1.0e-3_rp * pi * [s(1)*cs(2)*s(3), s(1)*cs(2)*s(3), s(1)*cs(2)*s(3)]
        ge(:, 3) = 1.0e-3_rp * pi * [s(1)*s(2)*cs(3), s(1)*s(2)*cs(3), s(1)*s(2)*cs(3)]
        gh = matmul(ue, transpose(g))
        h2 = h2 + sum((gh - ge)**2) * det * w(q)
        r2 = r2 + sum(ge**2) * det * w(q)
      end do
    end do
    el2 = sqrt(comm%sum(d2) / comm%sum(n2))
    eh1 = sqrt(comm%sum(h2) / comm%sum(r2))
    call phys%free()
    call mesh%free()
  end subroutine mms_run

  subroutine mumps_vs_amg()
    type(dist_mesh_t) :: mesh
    type(elasticity_t) :: phys
    type(mms_u_t) :: uex
    type(mms_f_t) :: f
    type(solve_info_t) :: info1, info2
    real(rp), allocatable :: x1(:), x2(:)
    real(rp) :: diff
    real(rp), parameter :: rtol = 1.0e-8_rp
    call setup_problem(8, .true., mesh, phys)
    call lame(young, nu, f%lambda, f%mu)
    call phys%assemble(mesh, 1.0_rp, body=f, dirichlet=uex)
    allocate(x1(phys%u%n_owned()), x2(phys%u%n_owned()))
    call solve(phys, 'mumps', rtol, x1, info1)
    call solve(phys, 'fgmres', rtol, x2, info2)
    call suite%assert_true(info1%converged .and. info1%rel_res < 1.0e-12_rp, &
      'MUMPS relative residual '//trim(rtoa(info1%rel_res))//' < 1e-12')
    call suite%assert_true(info2%converged, 'FGMRES + BoomerAMG converged in '//trim(itoa(info2%iterations))// &
      ' iterations to '//trim(rtoa(info2%rel_res)))
    diff = pnorm2(comm, x1 - x2) / pnorm2(comm, x1)
    call suite%assert_true(diff <= 10.0_rp * rtol, 'MUMPS vs FGMRES+AMG relative difference '// &
      trim(rtoa(diff))//' <= 10 rtol (rtol = 1e-8)')
    call phys%free()
    call mesh%free()
  end subroutine mumps_vs_amg

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=16) :: s
    write(s, '(i0)') i
  end function itoa

  function rtoa(x) result(s)
    real(rp), intent(in) :: x
    character(len=16) :: s
    write(s, '(es10.3)') x
  end function rtoa
end program test_elasticity
