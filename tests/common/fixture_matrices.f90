!> Test matrices and helpers shared by the unit tests of the numerics layer
!> (test_afsai, test_block_fsai, test_boomeramg, test_hypre_fsai):
!>
!>   build_laplacian  nf interleaved 7-point Laplacians on an n^3 grid of
!>                    nodes, split into contiguous ranges by rank, as a
!>                    csr_matrix_t with its row and column maps
!>   sort_row         short rows sorted by local column id, values alongside
!>   q1_entry, q1_mass  1D Q1 stiffness and mass entries (unit cells), the
!>                    factors of tensor-product test matrices
!>   wiggle           a symmetric relative perturbation of a few ulps that
!>                    depends on the number of ranks (rank-independence
!>                    tests must tolerate round-off, not rely on bits)
!>   test_arguments   the optional command line [file [scale]]
!>   write_entries    a distributed factor written on rank 0 as (row key,
!>                    column key, value) lines sorted by keys, so that runs
!>                    on different rank counts can be compared entry by entry
module fixture_matrices
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use index_map, only: index_map_t, sort_gids
  use csr_matrix, only: csr_matrix_t
  use global_csr, only: global_csr_t
  implicit none
  private

  public :: build_laplacian, sort_row, q1_entry, q1_mass, wiggle, test_arguments, write_entries

contains

  !> nf 7-point Laplacians (component c scaled by scale(c)) on an n^3 grid of
  !> nodes, Dirichlet boundary eliminated, interleaved unknowns; with
  !> coupling, components 1 and 2 of each node are linked by -coupling.
  !> Nodes are split into contiguous ranges by rank; the maps and the matrix
  !> are built here with the ghost columns of the neighbouring ranks.
  subroutine build_laplacian(comm, n, nf, scale, row_map, col_map, a, coupling)
    type(parallel_comm_t), intent(in) :: comm
    integer, intent(in) :: n, nf
    real(rp), intent(in) :: scale(:)
    real(rp), intent(in), optional :: coupling
    type(index_map_t), intent(inout), target :: row_map, col_map
    type(csr_matrix_t), intent(inout) :: a
    integer(gp) :: n_nodes, first_node, node, first, last, g
    integer(gp), allocatable :: gcol(:), ghosts(:), no_ghosts(:)
    integer(ip), allocatable :: row_ptr(:), col(:), pos(:), lc(:)
    real(rp), allocatable :: v(:)
    integer(ip) :: n_owned, own_nodes, i, k, m, ng
    integer :: c, ix, iy, iz, d
    integer, parameter :: step(3, 6) = reshape([-1,0,0, 1,0,0, 0,-1,0, 0,1,0, 0,0,-1, 0,0,1], [3, 6])
    integer :: nb(3)

    n_nodes = int(n, gp)**3
    own_nodes = int(n_nodes / comm%size, ip)
    if (comm%rank < mod(n_nodes, int(comm%size, gp))) own_nodes = own_nodes + 1
    first_node = comm%exscan_g(int(own_nodes, gp)) + 1
    n_owned = nf * own_nodes
    first = nf * (first_node - 1) + 1
    last = first + n_owned - 1

    ! pattern with global column ids: diagonal first, then up to 6 neighbours
    allocate(row_ptr(n_owned + 1), gcol(8 * n_owned), v(8 * n_owned))
    row_ptr(1) = 1
    k = 0
    do i = 1, n_owned
      g = first + i - 1
      node = (g - 1) / nf
      c = int(mod(g - 1, int(nf, gp))) + 1
      ix = int(mod(node, int(n, gp)))
      iy = int(mod(node / n, int(n, gp)))
      iz = int(node / (int(n, gp) * n))
      k = k + 1
      gcol(k) = g
      v(k) = 6.0_rp * scale(c)
      do d = 1, 6
        nb = [ix, iy, iz] + step(:, d)
        if (any(nb < 0) .or. any(nb >= n)) cycle
        k = k + 1
        gcol(k) = nf * (nb(1) + int(n, gp) * nb(2) + int(n, gp)**2 * nb(3)) + c
        v(k) = -scale(c)
      end do
      if (present(coupling) .and. nf >= 2 .and. c <= 2) then
        k = k + 1
        gcol(k) = g + 3 - 2 * c
        v(k) = -coupling
      end if
      row_ptr(i + 1) = k + 1
    end do

    ! ghost columns: the distinct global ids outside [first, last]
    ghosts = pack(gcol(1:k), gcol(1:k) < first .or. gcol(1:k) > last)
    allocate(pos(size(ghosts)))
    call sort_gids(ghosts, pos)
    ng = 0
    do m = 1, size(ghosts)
      if (ng > 0) then
        if (ghosts(m) == ghosts(ng)) cycle
      end if
      ng = ng + 1
      ghosts(ng) = ghosts(m)
    end do
    allocate(no_ghosts(0))
    call row_map%init(comm, n_owned, no_ghosts)
    call col_map%init(comm, n_owned, ghosts(1:ng))

    ! local column ids, ascending within each row
    allocate(col(k), lc(8))
    do i = 1, n_owned
      m = row_ptr(i + 1) - row_ptr(i)
      do d = 1, m
        lc(d) = col_map%local_id(gcol(row_ptr(i) + d - 1))
      end do
      call sort_row(lc(1:m), v(row_ptr(i):row_ptr(i + 1) - 1))
      col(row_ptr(i):row_ptr(i + 1) - 1) = lc(1:m)
    end do
    call a%init(row_map, col_map, row_ptr, col)
    a%val = v(1:k)
  end subroutine build_laplacian

  !> Insertion sort of a short row by local column id, values alongside.
  subroutine sort_row(lc, v)
    integer(ip), intent(inout) :: lc(:)
    real(rp), intent(inout) :: v(:)
    integer :: i, j
    integer(ip) :: tc
    real(rp) :: tv
    do i = 2, size(lc)
      tc = lc(i)
      tv = v(i)
      j = i - 1
      do while (j >= 1)
        if (lc(j) <= tc) exit
        lc(j + 1) = lc(j)
        v(j + 1) = v(j)
        j = j - 1
      end do
      lc(j + 1) = tc
      v(j + 1) = tv
    end do
  end subroutine sort_row

  !> 1D Q1 stiffness entry (unit cells) between nodes i and j of n.
  pure real(rp) function q1_entry(i, j, n)
    integer, intent(in) :: i, j, n
    if (i /= j) then
      q1_entry = -1.0_rp
    else if (i == 0 .or. i == n - 1) then
      q1_entry = 1.0_rp
    else
      q1_entry = 2.0_rp
    end if
  end function q1_entry

  !> 1D Q1 mass entry (unit cells) between nodes i and j of n.
  pure real(rp) function q1_mass(i, j, n)
    integer, intent(in) :: i, j, n
    if (i /= j) then
      q1_mass = 1.0_rp / 6.0_rp
    else if (i == 0 .or. i == n - 1) then
      q1_mass = 2.0_rp / 6.0_rp
    else
      q1_mass = 4.0_rp / 6.0_rp
    end if
  end function q1_mass

  !> 1 + h eps with h in -2..2 from the pair of keys (symmetric) and the
  !> number of ranks: a perturbation that differs between rank counts.
  pure real(rp) function wiggle(k1, k2, n_ranks)
    integer(gp), intent(in) :: k1, k2
    integer, intent(in) :: n_ranks
    integer(gp) :: h
    h = mod(min(k1, k2) * 37_gp + max(k1, k2) * 11_gp + int(n_ranks, gp) * 7_gp, 5_gp) - 2_gp
    wiggle = 1.0_rp + real(h, rp) * epsilon(1.0_rp)
  end function wiggle

  !> The command line [file [scale]]: path '' and scale 0 when absent (or
  !> scale unreadable).
  subroutine test_arguments(path, scale)
    character(len=*), intent(out) :: path
    integer, intent(out) :: scale
    character(len=32) :: arg
    integer :: ios
    path = ''
    scale = 0
    if (command_argument_count() >= 1) call get_command_argument(1, path)
    if (command_argument_count() >= 2) then
      call get_command_argument(2, arg)
      read(arg, *, iostat=ios) scale
      if (ios /= 0) scale = 0
    end if
  end subroutine test_arguments

  !> Gather g's entries on rank 0 as (row key, column key, value), the
  !> column key of global column j being col_key(j), sorted by keys, and
  !> write them to path after a "# title" line (a new file for the first
  !> block, appended after that). Collective.
  subroutine write_entries(comm, g, col_key, path, title, first_block)
    type(parallel_comm_t), intent(in) :: comm
    type(global_csr_t), intent(in) :: g
    integer(gp), intent(in) :: col_key(:)
    character(len=*), intent(in) :: path, title
    logical, intent(in) :: first_block
    integer(gp), allocatable :: kr(:), kc(:), comb(:)
    real(rp), allocatable :: v(:)
    integer(ip), allocatable :: pos(:), counts(:)
    integer(ip) :: cnt(1), i, k, m, p, u
    integer(gp) :: big
    m = g%nnz()
    cnt(1) = m
    allocate(counts(0:comm%size-1))
    counts = 0
    counts(0) = m
    if (comm%rank > 0) then
      call comm%send(cnt, 0, 11)
    else
      do p = 1, comm%size - 1
        call comm%recv(cnt, p, 11)
        counts(p) = cnt(1)
      end do
    end if
    allocate(kr(sum(counts)), kc(sum(counts)), v(sum(counts)))
    do i = 1, g%n_rows
      do k = g%row_ptr(i), g%row_ptr(i+1) - 1
        kr(k) = g%key(i)
        kc(k) = col_key(g%gcol(k))
        v(k) = g%val(k)
      end do
    end do
    if (comm%rank > 0) then
      call comm%send(kr, 0, 12)
      call comm%send(kc, 0, 13)
      call comm%send(v, 0, 14)
      return
    end if
    do p = 1, comm%size - 1
      call comm%recv(kr(m+1:m+counts(p)), p, 12)
      call comm%recv(kc(m+1:m+counts(p)), p, 13)
      call comm%recv(v(m+1:m+counts(p)), p, 14)
      m = m + counts(p)
    end do
    big = maxval(kc) + 1
    allocate(comb(m), pos(m))
    comb = kr * big + kc
    call sort_gids(comb, pos)
    if (first_block) then
      open(newunit=u, file=path, status='replace', action='write')
    else
      open(newunit=u, file=path, status='old', position='append', action='write')
    end if
    write(u, '(a)') '# '//title
    do k = 1, m
      write(u, '(i0,1x,i0,1x,es24.16e3)') kr(pos(k)), kc(pos(k)), v(pos(k))
    end do
    close(u)
  end subroutine write_entries
end module fixture_matrices
