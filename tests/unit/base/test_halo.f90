!> Unit tests of index_map_t: numbering, ownership, and the two halo
!> exchanges (import: owner -> ghost copies; export_add: ghosts -> owner).
!>
!> Every rank can compute every other rank's layout (the owned counts and
!> ghost lists below are functions of the rank), so the expected values are
!> known independently of the exchange. Meant for 2 ranks; 1 rank checks the
!> local numbering only; 3 or 4 ranks (--oversubscribe) exercise several
!> neighbours per rank.
program test_halo
  use kinds, only: rp, ip, gp
  use parallel_comm, only: parallel_comm_t
  use index_map, only: index_map_t
  use assertions, only: test_suite_t
  implicit none

  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite

  call comm%init_world()
  call suite%init('halo', comm)
  call check_layout(.false.)
  call check_layout(.true.)
  call suite%finish()

contains

  !> Entries owned by rank p: unequal counts, and with with_empty the last
  !> rank (when there are several) owns nothing but still holds ghosts.
  integer(ip) function owned_count(p, np, with_empty)
    integer, intent(in) :: p, np
    logical, intent(in) :: with_empty
    owned_count = 5 + 3 * p
    if (with_empty .and. np > 1 .and. p == np - 1) owned_count = 0
  end function owned_count

  !> First global id of rank p.
  integer(gp) function first_of(p, np, with_empty)
    integer, intent(in) :: p, np
    logical, intent(in) :: with_empty
    integer :: q
    first_of = 1
    do q = 0, p - 1
      first_of = first_of + owned_count(q, np, with_empty)
    end do
  end function first_of

  !> Ghost list of rank p: from every other rank q that owns something, its
  !> last entry, its first entry and (when it has one) its third entry, in
  !> that order, and ranks visited from the highest down, so that the list
  !> is neither sorted nor grouped by owner in rank order.
  subroutine ghosts_of(p, np, with_empty, gh)
    integer, intent(in) :: p, np
    logical, intent(in) :: with_empty
    integer(gp), allocatable, intent(out) :: gh(:)
    integer(gp) :: buf(3 * np)
    integer :: q, n, nq
    integer(gp) :: f
    n = 0
    do q = np - 1, 0, -1
      nq = owned_count(q, np, with_empty)
      if (q == p .or. nq == 0) cycle
      f = first_of(q, np, with_empty)
      n = n + 1
      buf(n) = f + nq - 1
      n = n + 1
      buf(n) = f
      if (nq >= 3 .and. mod(p + q, 2) == 1) then
        n = n + 1
        buf(n) = f + 2
      end if
    end do
    allocate(gh(n))
    gh = buf(1:n)
  end subroutine ghosts_of

  !> How many ranks hold global id g as a ghost; weighted: each rank p
  !> counts p + 1 instead of 1.
  integer function copies_of(g, np, with_empty, weighted)
    integer(gp), intent(in) :: g
    integer, intent(in) :: np
    logical, intent(in) :: with_empty
    logical, intent(in), optional :: weighted
    integer(gp), allocatable :: gh(:)
    integer :: p, w
    copies_of = 0
    do p = 0, np - 1
      call ghosts_of(p, np, with_empty, gh)
      w = 1
      if (present(weighted)) then
        if (weighted) w = p + 1
      end if
      copies_of = copies_of + w * count(gh == g)
    end do
  end function copies_of

  subroutine check_layout(with_empty)
    logical, intent(in) :: with_empty
    type(index_map_t) :: map
    integer(gp), allocatable :: gh(:)
    real(rp), allocatable :: x(:), expect(:)
    integer(gp) :: g, n_global
    integer(ip) :: i, nown, p_owner
    integer :: me, np, p
    logical :: ok
    character(len=32) :: tag

    me = comm%rank
    np = comm%size
    tag = merge(' (one rank owns nothing)', '                        ', with_empty)
    nown = owned_count(me, np, with_empty)
    call ghosts_of(me, np, with_empty, gh)
    call map%init(comm, nown, gh)

    ! sizes and offsets
    n_global = first_of(np, np, with_empty) - 1
    call suite%assert_true(map%n_owned == nown .and. map%n_ghost == size(gh) .and. &
                           map%n_local() == nown + size(gh), 'n_owned, n_ghost, n_local'//trim(tag))
    call suite%assert_true(map%n_global == n_global, 'n_global is the sum of the owned counts'//trim(tag))
    call suite%assert_true(map%first == first_of(me, np, with_empty), &
                           'first global id in rank order'//trim(tag))

    ! owner_of for every global id
    ok = .true.
    do p = 0, np - 1
      do g = first_of(p, np, with_empty), first_of(p, np, with_empty) + owned_count(p, np, with_empty) - 1
        p_owner = map%owner_of(g)
        ok = ok .and. p_owner == p
      end do
    end do
    call suite%assert_true(ok, 'owner_of every global id'//trim(tag))

    ! round trips local -> global -> local, and ghosts where they were given
    ok = .true.
    do i = 1, map%n_local()
      ok = ok .and. map%local_id(map%global_id(i)) == i
    end do
    do i = 1, map%n_ghost
      ok = ok .and. map%global_id(nown + i) == gh(i)
    end do
    call suite%assert_true(ok, 'local_id(global_id(i)) == i, ghosts in the given order'//trim(tag))
    ok = .true.
    do g = 1, n_global
      i = map%local_id(g)
      if (g >= map%first .and. g < map%first + nown) then
        ok = ok .and. i == g - map%first + 1
      else if (any(gh == g)) then
        ok = ok .and. i > nown .and. map%global_id(max(i, 1_ip)) == g
      else
        ok = ok .and. i == 0
      end if
    end do
    ok = ok .and. map%local_id(0_gp) == 0 .and. map%local_id(n_global + 1) == 0
    call suite%assert_true(ok, 'global_id(local_id(g)) == g, 0 for entries not held'//trim(tag))

    ! import: ghosts get the owners' values (value = global id)
    allocate(x(map%n_local()))
    do i = 1, nown
      x(i) = real(map%global_id(i), rp)
    end do
    x(nown+1:) = -1.0_rp
    call map%import(x)
    call suite%assert_close_array(x(nown+1:), real(gh, rp), 0.0_rp, &
                                  'import fills the ghosts with the owners'' values'//trim(tag))
    ok = .true.
    do i = 1, nown
      ok = ok .and. x(i) == real(map%global_id(i), rp)
    end do
    call suite%assert_true(ok, 'import leaves the owned entries alone'//trim(tag))

    ! export_add: each ghost copy adds 1 to its owner, ghosts are zeroed
    x(1:nown) = 10.0_rp
    x(nown+1:) = 1.0_rp
    call map%export_add(x)
    allocate(expect(nown))
    do i = 1, nown
      expect(i) = 10.0_rp + real(copies_of(map%global_id(i), np, with_empty), rp)
    end do
    call suite%assert_close_array(x(1:nown), expect, 0.0_rp, &
                                  'export_add: owners gain the number of their ghost copies'//trim(tag))
    call suite%assert_true(all(x(nown+1:) == 0.0_rp), 'export_add zeroes the ghosts'//trim(tag))
    if (np > 1 .and. .not. with_empty) then
      ! an id that several ranks copy got several contributions (3+ ranks)
      call suite%assert_true(comm%sum(int(sum(expect - 10.0_rp), ip)) == &
                             comm%sum(int(size(gh), ip)), 'every ghost copy arrived exactly once'//trim(tag))
    end if

    ! export_add of values that tell the copies apart (ghost's global id
    ! times its rank + 1): a mixed-up plan puts them on the wrong owners
    x(1:nown) = 0.0_rp
    x(nown+1:) = real(gh, rp) * (me + 1)
    call map%export_add(x)
    do i = 1, nown
      expect(i) = real(map%global_id(i), rp) * copies_of(map%global_id(i), np, with_empty, weighted=.true.)
    end do
    call suite%assert_close_array(x(1:nown), expect, 0.0_rp, &
                                  'export_add: each copy''s value reaches its owner'//trim(tag))

    ! import then export_add of owner values: owners gain value * copies
    do i = 1, nown
      x(i) = real(map%global_id(i), rp)
    end do
    x(nown+1:) = 0.0_rp
    call map%import(x)
    call map%export_add(x)
    do i = 1, nown
      expect(i) = real(map%global_id(i), rp) * (1 + copies_of(map%global_id(i), np, with_empty))
    end do
    call suite%assert_close_array(x(1:nown), expect, 0.0_rp, &
                                  'import then export_add: owners gain value times copies'//trim(tag))
    call map%free()
    call suite%assert_true(map%n_owned == 0 .and. map%n_ghost == 0, 'free resets the map'//trim(tag))
  end subroutine check_layout
end program test_halo
