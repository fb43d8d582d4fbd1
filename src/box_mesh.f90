!> Structured hexahedral box generator.
!>
!> nx*ny*nz cells on [x0,x1]x[y0,y1]x[z0,z1]; along each axis the cell sizes
!> may grow geometrically (grading = ratio of the last to the first cell size,
!> 1 = uniform). One region named "domain"; six boundary sets named
!> xmin, xmax, ymin, ymax, zmin, zmax.
module box_mesh
  use kinds, only: rp, ip, msg_len
  use error_status, only: error_status_t
  use mesh, only: mesh_t
  implicit none
  private

  public :: build_box_mesh, graded_points

contains

  !> Fill mesh with the box; n(3) cells per axis, lo(3)/hi(3) extents [m],
  !> grading(3) last/first cell size ratio per axis.
  subroutine build_box_mesh(mesh, n, lo, hi, grading, status)
    type(mesh_t), intent(inout) :: mesh
    integer(ip), intent(in) :: n(3)
    real(rp), intent(in) :: lo(3), hi(3), grading(3)
    type(error_status_t), intent(inout) :: status
    real(rp), allocatable :: px(:), py(:), pz(:)
    integer(ip) :: i, j, k, c, s, nxp, nyp
    character(len=msg_len) :: m

    if (any(n < 1)) then
      call status%set('box mesh: nx, ny and nz must be at least 1')
      return
    end if
    if (any(hi <= lo)) then
      call status%set('box mesh: each upper extent must exceed the lower one')
      return
    end if
    if (any(grading <= 0.0_rp)) then
      call status%set('box mesh: grading must be positive')
      return
    end if
    if (real(n(1)+1, rp) * real(n(2)+1, rp) * real(n(3)+1, rp) > real(huge(1_ip), rp)) then
      write(m, '(a)') 'box mesh: too many nodes for 32-bit local ids'
      call status%set(m)
      return
    end if
    call mesh%free()
    px = graded_points(n(1), lo(1), hi(1), grading(1))
    py = graded_points(n(2), lo(2), hi(2), grading(2))
    pz = graded_points(n(3), lo(3), hi(3), grading(3))
    nxp = n(1) + 1
    nyp = n(2) + 1
    mesh%n_nodes = nxp * nyp * (n(3) + 1)
    mesh%n_cells = n(1) * n(2) * n(3)
    allocate(mesh%coords(3, mesh%n_nodes))
    do k = 0, n(3)
      do j = 0, n(2)
        do i = 0, n(1)
          mesh%coords(:, node(i, j, k)) = [px(i+1), py(j+1), pz(k+1)]
        end do
      end do
    end do
    allocate(mesh%cell_nodes(8, mesh%n_cells), mesh%cell_region(mesh%n_cells))
    c = 0
    do k = 0, n(3) - 1
      do j = 0, n(2) - 1
        do i = 0, n(1) - 1
          c = c + 1
          mesh%cell_nodes(:, c) = [node(i, j, k), node(i+1, j, k), node(i+1, j+1, k), node(i, j+1, k), &
                                   node(i, j, k+1), node(i+1, j, k+1), node(i+1, j+1, k+1), node(i, j+1, k+1)]
        end do
      end do
    end do
    mesh%cell_region = 1
    allocate(mesh%region_names(1))
    mesh%region_names(1) = 'domain'

    allocate(mesh%set_names(6))
    mesh%set_names = [character(len=len(mesh%set_names)) :: 'xmin', 'xmax', 'ymin', 'ymax', 'zmin', 'zmax']
    mesh%n_sfaces = 2 * (n(2)*n(3) + n(1)*n(3) + n(1)*n(2))
    allocate(mesh%sface_nodes(4, mesh%n_sfaces), mesh%sface_set(mesh%n_sfaces))
    s = 0
    do k = 0, n(3) - 1
      do j = 0, n(2) - 1
        call add(1, [node(0, j, k), node(0, j, k+1), node(0, j+1, k+1), node(0, j+1, k)])
        call add(2, [node(n(1), j, k), node(n(1), j+1, k), node(n(1), j+1, k+1), node(n(1), j, k+1)])
      end do
    end do
    do k = 0, n(3) - 1
      do i = 0, n(1) - 1
        call add(3, [node(i, 0, k), node(i+1, 0, k), node(i+1, 0, k+1), node(i, 0, k+1)])
        call add(4, [node(i, n(2), k), node(i, n(2), k+1), node(i+1, n(2), k+1), node(i+1, n(2), k)])
      end do
    end do
    do j = 0, n(2) - 1
      do i = 0, n(1) - 1
        call add(5, [node(i, j, 0), node(i, j+1, 0), node(i+1, j+1, 0), node(i+1, j, 0)])
        call add(6, [node(i, j, n(3)), node(i+1, j, n(3)), node(i+1, j+1, n(3)), node(i, j+1, n(3))])
      end do
    end do
    call mesh%build_faces(status)
  contains
    pure integer(ip) function node(i, j, k)
      integer(ip), intent(in) :: i, j, k
      node = 1 + i + nxp * (j + nyp * k)
    end function node
    subroutine add(set, q)
      integer(ip), intent(in) :: set, q(4)
      s = s + 1
      mesh%sface_nodes(:, s) = q
      mesh%sface_set(s) = set
    end subroutine add
  end subroutine build_box_mesh

  !> n+1 points from a to b whose spacing grows geometrically so that the last
  !> interval is `ratio` times the first.
  function graded_points(n, a, b, ratio) result(p)
    integer(ip), intent(in) :: n
    real(rp), intent(in) :: a, b, ratio
    real(rp) :: p(n+1)
    real(rp) :: q, h, w
    integer(ip) :: i
    p(1) = a
    if (n == 1 .or. abs(ratio - 1.0_rp) < 1.0e-12_rp) then
      do i = 1, n
        p(i+1) = a + (b - a) * real(i, rp) / real(n, rp)
      end do
    else
      q = ratio ** (1.0_rp / real(n - 1, rp))
      w = (q ** n - 1.0_rp) / (q - 1.0_rp)
      h = (b - a) / w
      do i = 1, n
        p(i+1) = p(i) + h * q ** (i - 1)
      end do
    end if
    p(n+1) = b
  end function graded_points
end module box_mesh
