!> Settings of geoblock's adaptive sparse approximate inverses: the adaptive
!> FSAI factor (afsai) and the block-FSAI decoupling factors (block_fsai).
!>
!> Both grow the pattern of each row (FSAI) or column (decoupling factor) in
!> steps, adding the entries that promise the largest gain, after Janna and
!> Ferronato, SIAM J. Sci. Comput. 33 (2011) 3357-3380, and FSAIPACK (Janna,
!> Ferronato, Sartoretto, Gambolati, ACM TOMS 41 (2015)). The defaults follow
!> the orders of magnitude of those papers (a few steps of a few entries):
!>   max_steps 5, step_size 4 : at most 20 entries added per row or column,
!>                              about the size of a 27-point stencil row;
!>   tol 1e-4                 : a row stops when a step would lower its
!>                              objective by less than 0.01 % (with 1e-3
!>                              the rows stopped early: Mandel at the seed's
!>                              size, explicit aFSAI, gamma = 100, mu 0.90,
!>                              0.91 and 0.92 with 5, 6 and 8 steps, 219
!>                              iterations; with 1e-4 and 5 steps mu 1.01,
!>                              198 iterations, the seed's 210 at mu 1.57);
!>   init 'lower'             : the static start of FSAIPACK (the lower
!>                              triangle of A's pattern);
!>   drop 0                   : keep every entry found.
module fsai_params
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds, only: rp, name_len
  use error_status, only: error_status_t
  use strings, only: itoa, rtoa
  implicit none
  private

  public :: fsai_params_t

  !> Settings of the adaptive pattern search (see the module header).
  type :: fsai_params_t
    !> adaptive steps per row (column); 0 keeps the initial pattern
    integer :: max_steps = 5
    !> entries added per row (column) and step, the most promising first
    integer :: step_size = 4
    !> FSAI: a row stops when a step lowers (or is predicted to lower) its
    !> diagonal g^T A g by less than the fraction tol; decoupling factors: a
    !> column stops when ||c - K f|| <= tol ||c||. 0: never stop early.
    real(rp) :: tol = 1.0e-4_rp
    !> FSAI start: 'lower' (the entries of A's row with a smaller key) or
    !> 'diagonal' (the diagonal alone). Decoupling factors always start from
    !> the pattern of the right-hand-side column.
    character(len=name_len) :: init = 'lower'
    !> after the last step, drop the entries of a row (column) with
    !> |v| < drop * max |v| of that row (column); never an FSAI diagonal.
    !> 0 keeps everything.
    real(rp) :: drop = 0.0_rp
  contains
    procedure :: validate
  end type fsai_params_t

contains

  !> Range-check every field; the first bad one is reported in status by
  !> name, value and accepted range. Not collective (the settings are the
  !> same on every rank).
  subroutine validate(self, status)
    class(fsai_params_t), intent(in) :: self
    type(error_status_t), intent(inout) :: status
    if (self%max_steps < 0 .or. self%max_steps > 1000) then
      call status%set('fsai_params: max_steps = '//itoa(self%max_steps)// &
                      ' is not valid; expected an integer in 0..1000')
    else if (self%step_size < 1) then
      call status%set('fsai_params: step_size = '//itoa(self%step_size)// &
                      ' is not valid; expected a positive integer')
    else if (.not. (ieee_is_finite(self%tol) .and. self%tol >= 0.0_rp .and. self%tol < 1.0_rp)) then
      call status%set('fsai_params: tol = '//rtoa(self%tol)//' is not valid; expected a real in [0, 1)')
    else if (trim(self%init) /= 'lower' .and. trim(self%init) /= 'diagonal') then
      call status%set('fsai_params: init = '''//trim(self%init)// &
                      ''' is not valid; expected one of: lower, diagonal')
    else if (.not. (ieee_is_finite(self%drop) .and. self%drop >= 0.0_rp .and. self%drop < 1.0_rp)) then
      call status%set('fsai_params: drop = '//rtoa(self%drop)//' is not valid; expected a real in [0, 1)')
    end if
  end subroutine validate
end module fsai_params
