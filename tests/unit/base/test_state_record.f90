!> state_record: arrays kept by name and given back exactly; a missing
!> name, another size or another type is an error that names the entry.
program test_state_record
  use kinds, only: rp
  use parallel_comm, only: parallel_comm_t
  use error_status, only: error_status_t
  use state_record, only: state_record_t
  use assertions, only: test_suite_t
  implicit none
  type(parallel_comm_t) :: comm
  type(test_suite_t) :: suite
  type(state_record_t) :: st
  type(error_status_t) :: status
  real(rp) :: x(5), y(5), z(4)
  integer :: s(3), s2(3)
  integer :: k

  call comm%init_world()
  call suite%init('state_record', comm)
  x = [1.0_rp, -2.5_rp, 3.0e-300_rp, huge(1.0_rp), 0.1_rp]
  s = [1, 2, 3]
  call st%put('x', x)
  call st%put('status', s)
  y = 0.0_rp
  call st%get('x', y, status)
  call suite%assert_true(status%ok() .and. all(y == x), 'a real array comes back bit for bit')
  s2 = 0
  call st%get('status', s2, status)
  call suite%assert_true(status%ok() .and. all(s2 == s), 'an integer array comes back')
  call st%put('x', 2.0_rp * x)
  call st%get('x', y, status)
  call suite%assert_true(status%ok() .and. all(y == 2.0_rp * x) .and. st%n == 2, 'put replaces an entry of the same name')
  call st%get('u', y, status)
  call suite%assert_true(index(status%msg, "no entry 'u'") > 0, 'a missing entry is named: '//trim(status%msg))
  call status%clear()
  call st%get('x', z, status)
  call suite%assert_true(index(status%msg, "'x' has 5 values, the state needs 4") > 0, &
                         'another size is an error: '//trim(status%msg))
  call status%clear()
  call st%get('status', y(1:3), status)
  call suite%assert_true(index(status%msg, 'not a real array') > 0, 'another type is an error: '//trim(status%msg))
  call status%clear()
  do k = 1, 20
    call st%put('entry'//achar(iachar('a') + mod(k, 26)), [real(k, rp)])
  end do
  call st%get('x', y, status)
  call suite%assert_true(status%ok() .and. all(y == 2.0_rp * x), 'entries survive the record growing')
  call st%clear()
  call st%get('x', y, status)
  call suite%assert_true(.not. status%ok() .and. st%n == 0, 'clear forgets every entry')
  call suite%finish()
  call comm%finalize()
end program test_state_record
