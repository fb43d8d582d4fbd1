!> Is the displacement of every piece of the mesh determined? Each piece
!> (mesh_pieces.f90), or group of pieces joined by interface elements that
!> hold, must have its six rigid-body motions (three translations, three
!> rotations) stopped by prescribed displacement components; otherwise the
!> stiffness matrix is singular and a solver would fail late (a Krylov
!> breakdown) or, worse, return a meaningless field.
!>
!> For a group with prescribed components (node x, component c), the rigid
!> motion with translation a and rotation w gives u_c(x) = a_c + (w x y)_c,
!> y = (x - x0) / L (x0 the centre of the group's bounding box, L its size).
!> The motion is stopped iff it vanishes at every prescribed component, i.e.
!> iff the 6 x 6 matrix G = sum over prescribed components of r r^T, r =
!> (e_c, y x e_c), is nonsingular. Each rank adds up, per local component,
!> the count, first and second moments of the prescribed nodes' y per c;
!> rank 0 shifts them to x0, builds G per group and takes its eigenvalues
!> (LAPACK dsyev): a smallest eigenvalue below 1e-10 times the largest is a
!> free motion, named by its eigenvector.
module rigid_modes
  use kinds, only: rp, ip, gp, msg_len
  use error_status, only: error_status_t
  use dist_mesh, only: dist_mesh_t
  use mesh_pieces, only: mesh_pieces_t
  implicit none
  private

  public :: check_rigid_modes

  !> record of a local component sent to rank 0: label, nodes, bbox(6),
  !> reference point (3), per component c: count, sum y (3), sum y y^T (6)
  integer, parameter :: rec_len = 11 + 3 * 10
  real(rp), parameter :: free_ratio = 1.0e-10_rp
  character(len=18), parameter :: mode_names(6) = [character(len=18) :: 'translation in x', 'translation in y', &
    'translation in z', 'rotation about x', 'rotation about y', 'rotation about z']

  interface
    subroutine dsyev(jobz, uplo, n, a, lda, w, work, lwork, info)
      import :: rp
      character, intent(in) :: jobz, uplo
      integer, intent(in) :: n, lda, lwork
      real(rp), intent(inout) :: a(lda, *)
      real(rp), intent(out) :: w(*), work(*)
      integer, intent(out) :: info
    end subroutine dsyev
  end interface

contains

  !> Set status (the same on every rank) when a group of pieces can move as
  !> a rigid body. fixed(c, i): component c of local node i is prescribed.
  !> joins(2, m): labels of pieces joined by an owned interface element that
  !> holds (absent: none). Collective.
  subroutine check_rigid_modes(mesh, pieces, fixed, status, joins)
    type(dist_mesh_t), intent(in) :: mesh
    type(mesh_pieces_t), intent(in) :: pieces
    logical, intent(in) :: fixed(:,:)
    type(error_status_t), intent(inout) :: status
    integer(gp), intent(in), optional :: joins(:,:)
    real(rp), allocatable :: rec(:,:), all_rec(:,:), jrec(:,:), all_j(:,:)
    character(len=msg_len) :: msg
    integer(ip) :: nj
    call local_records(mesh, pieces, fixed, rec)
    nj = 0
    if (present(joins)) nj = int(size(joins, 2), ip)
    allocate(jrec(2, nj))
    if (nj > 0) jrec = real(joins, rp)
    call gather_on_root(mesh, rec, all_rec)
    call gather_on_root(mesh, jrec, all_j)
    msg = ''
    if (mesh%comm%is_root()) call judge(all_rec, all_j, present(joins), msg)
    call mesh%comm%bcast(msg)
    if (len_trim(msg) > 0) call status%set(trim(msg), 1)
  end subroutine check_rigid_modes

  !> One record per local component that holds owned nodes.
  subroutine local_records(mesh, pieces, fixed, rec)
    type(dist_mesh_t), intent(in) :: mesh
    type(mesh_pieces_t), intent(in) :: pieces
    logical, intent(in) :: fixed(:,:)
    real(rp), allocatable, intent(out) :: rec(:,:)
    integer(ip), allocatable :: slot(:)
    integer(ip) :: i, k, n, c, b
    real(rp) :: y(3)
    allocate(slot(pieces%n_comp))
    slot = 0
    n = 0
    do i = 1, mesh%n_owned_nodes()
      if (slot(pieces%comp(i)) == 0) then
        n = n + 1
        slot(pieces%comp(i)) = n
      end if
    end do
    allocate(rec(rec_len, n))
    rec = 0.0_rp
    rec(3:5, :) = huge(1.0_rp)
    rec(6:8, :) = -huge(1.0_rp)
    do i = 1, mesh%n_owned_nodes()
      k = slot(pieces%comp(i))
      rec(1, k) = real(pieces%label(i), rp)
      rec(2, k) = rec(2, k) + 1.0_rp
      rec(3:5, k) = min(rec(3:5, k), mesh%coords(:, i))
      rec(6:8, k) = max(rec(6:8, k), mesh%coords(:, i))
    end do
    rec(9:11, :) = 0.5_rp * (rec(3:5, :) + rec(6:8, :))
    do i = 1, mesh%n_owned_nodes()
      k = slot(pieces%comp(i))
      y = mesh%coords(:, i) - rec(9:11, k)
      do c = 1, 3
        if (.not. fixed(c, i)) cycle
        b = 11 + 10 * (c - 1)
        rec(b + 1, k) = rec(b + 1, k) + 1.0_rp
        rec(b + 2:b + 4, k) = rec(b + 2:b + 4, k) + y
        rec(b + 5:b + 10, k) = rec(b + 5:b + 10, k) + sym6(y, y)
      end do
    end do
  end subroutine local_records

  !> (a b^T + b a^T) / 2 as xx yy zz xy yz xz.
  pure function sym6(a, b) result(s)
    real(rp), intent(in) :: a(3), b(3)
    real(rp) :: s(6)
    s = [a(1)*b(1), a(2)*b(2), a(3)*b(3), 0.5_rp*(a(1)*b(2) + a(2)*b(1)), 0.5_rp*(a(2)*b(3) + a(3)*b(2)), &
         0.5_rp*(a(1)*b(3) + a(3)*b(1))]
  end function sym6

  !> The columns of every rank's rec, on rank 0 (rank order). Collective.
  subroutine gather_on_root(mesh, rec, all_rec)
    type(dist_mesh_t), intent(in) :: mesh
    real(rp), intent(in) :: rec(:,:)
    real(rp), allocatable, intent(out) :: all_rec(:,:)
    integer(ip) :: scount(0:mesh%comm%size-1), rcount(0:mesh%comm%size-1)
    real(rp), allocatable :: flat(:)
    scount = 0
    scount(0) = int(size(rec), ip)
    call mesh%comm%alltoall_i(scount, rcount)
    allocate(flat(max(1, sum(rcount))))
    call mesh%comm%alltoallv(reshape(rec, [size(rec)]), scount, flat, rcount)
    allocate(all_rec(size(rec, 1), sum(rcount) / max(1, size(rec, 1))))
    if (size(all_rec) > 0) all_rec = reshape(flat(1:size(all_rec)), shape(all_rec))
  end subroutine gather_on_root

  !> Rank 0: group the records by piece and by joins, test each group; msg
  !> names the first group that can move ('' if none).
  subroutine judge(rec, joins, with_faults, msg)
    real(rp), intent(in) :: rec(:,:), joins(:,:)
    logical, intent(in) :: with_faults
    character(len=*), intent(out) :: msg
    integer(ip), allocatable :: grp(:), parent(:)
    real(rp), allocatable :: box(:,:), nodes(:), low(:)
    real(rp) :: g(6,6), x0(3), scale
    integer(ip) :: n, i, j, ng, a, b
    n = int(size(rec, 2), ip)
    msg = ''
    if (n == 0) return
    ! records of the same piece, and pieces joined by an interface, unite
    allocate(parent(n))
    parent = [(i, i = 1, n)]
    do i = 1, n
      do j = 1, i - 1
        if (rec(1, j) == rec(1, i)) then
          call unite(parent, i, j)
          exit
        end if
      end do
    end do
    do j = 1, size(joins, 2)
      a = first_of(rec, joins(1, j))
      b = first_of(rec, joins(2, j))
      if (a > 0 .and. b > 0) call unite(parent, a, b)
    end do
    ! groups numbered by their smallest label: the same for any partition
    allocate(grp(n), low(n))
    low = huge(1.0_rp)
    do i = 1, n
      low(root_of(parent, i)) = min(low(root_of(parent, i)), rec(1, i))
    end do
    ng = 0
    grp = 0
    do i = 1, n
      if (root_of(parent, i) == i) ng = ng + 1
    end do
    do i = 1, n
      if (root_of(parent, i) /= i) cycle
      grp(i) = 1 + count([(root_of(parent, j) == j .and. low(j) < low(i), j = 1, n)])
    end do
    do i = 1, n
      grp(i) = grp(root_of(parent, i))
    end do
    allocate(box(6, ng), nodes(ng))
    box(1:3, :) = huge(1.0_rp)
    box(4:6, :) = -huge(1.0_rp)
    nodes = 0.0_rp
    do i = 1, n
      box(1:3, grp(i)) = min(box(1:3, grp(i)), rec(3:5, i))
      box(4:6, grp(i)) = max(box(4:6, grp(i)), rec(6:8, i))
      nodes(grp(i)) = nodes(grp(i)) + rec(2, i)
    end do
    do j = 1, ng
      x0 = 0.5_rp * (box(1:3, j) + box(4:6, j))
      scale = max(maxval(box(4:6, j) - box(1:3, j)), tiny(1.0_rp))
      g = 0.0_rp
      do i = 1, n
        if (grp(i) == j) call add_moments(rec(:, i), x0, scale, g)
      end do
      call test_group(g, j, ng, box(:, j), nodes(j), with_faults, msg)
      if (len_trim(msg) > 0) return
    end do
  end subroutine judge

  integer(ip) function first_of(rec, label) result(k)
    real(rp), intent(in) :: rec(:,:), label
    do k = 1, int(size(rec, 2), ip)
      if (rec(1, k) == label) return
    end do
    k = 0
  end function first_of

  integer(ip) function root_of(parent, i) result(r)
    integer(ip), intent(in) :: parent(:), i
    r = i
    do while (parent(r) /= r)
      r = parent(r)
    end do
  end function root_of

  subroutine unite(parent, a, b)
    integer(ip), intent(inout) :: parent(:)
    integer(ip), intent(in) :: a, b
    integer(ip) :: ra, rb
    ra = root_of(parent, a)
    rb = root_of(parent, b)
    if (ra /= rb) parent(max(ra, rb)) = min(ra, rb)
  end subroutine unite

  !> Add to g the prescribed components of one record, with y = (x - x0) /
  !> scale (the record's moments are about its own reference point).
  subroutine add_moments(r, x0, scale, g)
    real(rp), intent(in) :: r(:), x0(3), scale
    real(rp), intent(inout) :: g(6,6)
    real(rp) :: d(3), cnt, s1(3), s2(3,3), e(3), a(3,3)
    integer :: c, b
    d = (r(9:11) - x0) / scale
    do c = 1, 3
      b = 11 + 10 * (c - 1)
      cnt = r(b + 1)
      if (cnt == 0.0_rp) cycle
      s1 = r(b + 2:b + 4) / scale
      s2 = unpack6(r(b + 5:b + 10)) / scale**2
      ! shift to x0: sum (y + d) = s1 + n d, sum (y + d)(y + d)^T
      s2 = s2 + outer(s1, d) + outer(d, s1) + cnt * outer(d, d)
      s1 = s1 + cnt * d
      e = 0.0_rp
      e(c) = 1.0_rp
      ! rotation row of component c: (w x y)_c = w . (y x e_c) = w^T A y, A = cross(., e_c)
      a = cross_matrix(e)
      g(c, c) = g(c, c) + cnt
      g(c, 4:6) = g(c, 4:6) + matmul(a, s1)
      g(4:6, c) = g(4:6, c) + matmul(a, s1)
      g(4:6, 4:6) = g(4:6, 4:6) + matmul(a, matmul(s2, transpose(a)))
    end do
  end subroutine add_moments

  !> A with A y = y x e.
  pure function cross_matrix(e) result(a)
    real(rp), intent(in) :: e(3)
    real(rp) :: a(3,3)
    a = reshape([0.0_rp, -e(3), e(2), e(3), 0.0_rp, -e(1), -e(2), e(1), 0.0_rp], [3, 3])
  end function cross_matrix

  pure function outer(a, b) result(m)
    real(rp), intent(in) :: a(3), b(3)
    real(rp) :: m(3,3)
    m = spread(a, 2, 3) * spread(b, 1, 3)
  end function outer

  pure function unpack6(s) result(m)
    real(rp), intent(in) :: s(6)
    real(rp) :: m(3,3)
    m = reshape([s(1), s(4), s(6), s(4), s(2), s(5), s(6), s(5), s(3)], [3, 3])
  end function unpack6

  !> msg when group j (of ng) can move: its free motions by eigenvector.
  subroutine test_group(g, j, ng, box, nodes, with_faults, msg)
    real(rp), intent(in) :: g(6,6), box(6), nodes
    integer(ip), intent(in) :: j, ng
    logical, intent(in) :: with_faults
    character(len=*), intent(out) :: msg
    real(rp) :: a(6,6), w(6), work(64)
    integer :: info, k, n_free
    character(len=200) :: modes, where, tmp
    a = g
    call dsyev('V', 'U', 6, a, 6, w, work, size(work), info)
    msg = ''
    if (info /= 0) return
    if (w(6) > 0.0_rp .and. w(1) > free_ratio * w(6)) return
    modes = ''
    n_free = 0
    do k = 1, 6
      if (w(k) > free_ratio * max(w(6), tiny(1.0_rp))) exit
      if (n_free > 0) modes = trim(modes)//','
      modes = trim(modes)//' '//trim(mode_names(maxloc(abs(a(:, k)), 1)))
      n_free = n_free + 1
    end do
    write(where, '(a,i0,a,6(g0.4,a))') ' (', nint(nodes), ' nodes in x ', box(1), ' .. ', box(4), &
      ', y ', box(2), ' .. ', box(5), ', z ', box(3), ' .. ', box(6), ' m)'
    tmp = where
    if (ng > 1) write(where, '(a,i0,a,i0,a)') ' piece ', j, ' of ', ng, trim(tmp)
    msg = 'the mesh'//trim(where)//' can move as a rigid body: its displacement conditions leave free'// &
          trim(modes)//"; prescribe displacements on it (&boundary type = 'displacement')"
    if (ng > 1 .and. with_faults) then
      msg = trim(msg)//' or join it to the rest through a fault that is not open'
    else if (ng > 1) then
      msg = trim(msg)//' or join it to the rest of the mesh (cells that share no node are not connected)'
    end if
  end subroutine test_group
end module rigid_modes
