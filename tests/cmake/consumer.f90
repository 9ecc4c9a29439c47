!> A minimal Fortran consumer of tricell::fortran: the 12 nearest neighbours of FCC.
program consumer
    use, intrinsic :: iso_c_binding, only: c_double
    use tricell
    implicit none
    type(tricell_neighbor_list) :: list
    real(c_double) :: box(3, 3), x(3, 1)
    integer :: status

    box = 0
    box(:, 1) = [0d0, 1.8d0, 1.8d0]
    box(:, 2) = [1.8d0, 0d0, 1.8d0]
    box(:, 3) = [1.8d0, 1.8d0, 0d0]
    x = 0
    list = tricell_neighbor_list(3d0)
    call list%compute(x, box, [.true., .true., .true.], status)
    if (status /= TRICELL_OK .or. list%npairs /= 12) then
        print '(2a)', 'tricell Fortran consumer failed: ', tricell_errmsg()
        error stop 1
    end if
    call list%destroy()
    print '(2a)', 'tricell Fortran consumer ok, tricell ', tricell_version()
end program
