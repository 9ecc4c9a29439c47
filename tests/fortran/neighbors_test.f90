!> The Fortran module against the C++ API and the brute-force oracle (oracle.cpp) on random
!> seeded systems: general triclinic boxes, every combination of periodic axes, cutoffs up to
!> several times the box, atoms far outside it. Also checks, in Fortran, that D, d and the
!> offsets agree with the positions as Fortran sees them, and the error paths.
program neighbors_test
    use, intrinsic :: iso_c_binding
    use tricell
    implicit none

    interface
        function check_list(positions, n, box, periodic, cutoff, half, order, backend, radii, &
                            species, table_pairs, table_cutoffs, table_count, npairs, i, j, &
                            shifts, distances, vectors) bind(c, name="tricell_test_check_list")
            import :: c_int, c_double, c_size_t, c_int32_t, c_ptr
            real(c_double), intent(in) :: positions(*), box(*)
            integer(c_size_t), value :: n, npairs, table_count
            integer(c_int), intent(in) :: periodic(3)
            real(c_double), value :: cutoff
            integer(c_int), value :: half, order, backend
            type(c_ptr), value :: radii, species, table_pairs, table_cutoffs
            integer(c_int32_t), intent(in) :: i(*), j(*), shifts(*)
            real(c_double), intent(in) :: distances(*), vectors(*)
            integer(c_int) :: check_list
        end function
    end interface

    integer :: cases
    integer :: seed, failures, total_pairs, beyond_box, partial
    character(len=16) :: argument

    cases = 300
    if (command_argument_count() >= 1) then
        call get_command_argument(1, argument)
        read (argument, *) cases
    end if
    failures = 0
    total_pairs = 0
    beyond_box = 0
    partial = 0
    do seed = 1, cases
        call random_case(seed)
    end do
    call verlet_trajectories(max(cases / 10, 5))
    call nearest_in_a_molecule()
    call error_paths()
    if (total_pairs < 1000 .or. beyond_box == 0 .or. partial == 0) then
        print '(a)', 'the random cases are too easy'
        failures = failures + 1
    end if
    if (failures /= 0) then
        print '(i0, a)', failures, ' failures'
        error stop 1
    end if
    print '(a, i0, a, i0, a)', 'tricell Fortran module: ok (', cases, ' systems, ', &
        total_pairs, ' pairs)'

contains

    subroutine random_case(seed)
        integer, intent(in) :: seed
        type(tricell_neighbor_list) :: list
        real(c_double) :: box(3, 3), u(3, 3), cutoff, lengths(3), widths(3), r
        real(c_double), allocatable, target :: x(:, :), radii(:)
        integer(c_int32_t), allocatable, target :: species(:)
        ! Species pairs 0-0, 0-1 and 2-2 (1-1, 1-2 and 0-2 are missing: never counted).
        integer, target :: table_pairs(2, 3) = reshape([0, 0, 0, 1, 2, 2], [2, 3])
        real(c_double), target :: table_cutoffs(3)
        logical :: periodic(3), half, sorted, grouped
        integer(c_int) :: order
        integer :: n, k, a, status, problems, bits, backend, rule
        integer, allocatable :: seeds(:)

        call random_seed(size=k)
        allocate (seeds(k))
        seeds = 7919 * seed + [(a, a=1, k)]
        call random_seed(put=seeds)

        ! A general triclinic box: lengths in [2, 8], every component tilted.
        call random_number(lengths)
        lengths = 2 + 6 * lengths
        call random_number(u)
        do k = 1, 3
            box(:, k) = 0.6d0 * lengths(k) * (u(:, k) - 0.5d0)
            box(k, k) = box(k, k) + lengths(k)
        end do
        call random_number(r)
        bits = int(8 * r)
        periodic = [btest(bits, 0), btest(bits, 1), btest(bits, 2)]
        if (.not. all(periodic)) partial = partial + 1
        widths = perpendicular_widths(box)
        call random_number(r)
        cutoff = minval(widths) * (0.3d0 + 2.2d0 * r) ! up to 2.5 times the thinnest width
        if (cutoff > minval(widths)) beyond_box = beyond_box + 1
        call random_number(r)
        n = int(41 * r)
        allocate (x(3, n))
        call random_number(x)
        do a = 1, n
            call random_number(r)
            if (r < 0.2d0) then
                x(:, a) = x(:, a) + nint(100 * (x(:, a) - 0.5d0)) ! far outside
            else
                x(:, a) = 2 * x(:, a) - 0.5d0
            end if
            x(:, a) = matmul(box, x(:, a))
        end do
        call random_number(r)
        half = r < 0.5d0
        call random_number(r)
        sorted = r < 0.5d0
        grouped = .not. sorted .and. r < 0.75d0
        order = merge(1, merge(2, 0, grouped), sorted) ! as check_list takes it

        call random_number(r)
        backend = int(4 * r) ! automatic, dense, linked, hash
        rule = mod(seed, 3) ! 0: one cutoff, 1: radii, 2: species (no pair beyond cutoff)
        if (n == 0) rule = 0 ! radii(0) cannot be told from no radii
        allocate (radii(n), species(n))
        call random_number(radii)
        radii = cutoff * (0.1d0 + 0.4d0 * radii)
        species = int(mod([(a, a=1, n)] * 7 + seed, 3), c_int32_t)
        table_cutoffs = cutoff * [0.5d0, 0.8d0, 1d0]
        select case (rule)
        case (0)
            list = tricell_neighbor_list(cutoff, half=half, sorted=sorted, grouped=grouped, &
                                         vectors=.true., backend=backend)
            call list%compute(x, box, periodic, status)
        case (1)
            list = tricell_neighbor_list(0d0, half=half, sorted=sorted, grouped=grouped, &
                                         vectors=.true., backend=backend)
            call list%compute(x, box, periodic, status, radii=radii)
        case default
            list = tricell_neighbor_list(0d0, half=half, sorted=sorted, grouped=grouped, &
                                         vectors=.true., backend=backend, &
                                         species_pairs=table_pairs, &
                                         species_cutoffs=table_cutoffs)
            call list%compute(x, box, periodic, status, species=species)
        end select
        if (status /= TRICELL_OK) then
            print '(a, i0, 2a)', 'seed ', seed, ': ', tricell_errmsg()
            failures = failures + 1
            return
        end if
        total_pairs = total_pairs + list%npairs
        if (rule == 0) then
            problems = check_list(x, int(n, c_size_t), box, merge(1, 0, periodic), cutoff, &
                                  merge(1, 0, half), order, int(backend, c_int), &
                                  c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, 0_c_size_t, &
                                  int(list%npairs, c_size_t), list%i, list%j, list%shifts, &
                                  list%distances, list%vectors)
        else if (rule == 1) then
            problems = check_list(x, int(n, c_size_t), box, merge(1, 0, periodic), 0d0, &
                                  merge(1, 0, half), order, int(backend, c_int), &
                                  c_loc(radii), c_null_ptr, c_null_ptr, c_null_ptr, 0_c_size_t, &
                                  int(list%npairs, c_size_t), list%i, list%j, list%shifts, &
                                  list%distances, list%vectors)
        else
            problems = check_list(x, int(n, c_size_t), box, merge(1, 0, periodic), 0d0, &
                                  merge(1, 0, half), order, int(backend, c_int), &
                                  c_null_ptr, c_loc(species), c_loc(table_pairs), &
                                  c_loc(table_cutoffs), 3_c_size_t, &
                                  int(list%npairs, c_size_t), list%i, list%j, list%shifts, &
                                  list%distances, list%vectors)
        end if
        problems = problems + check_in_fortran(list, x, box, cutoff, sorted .or. grouped)
        if (problems /= 0) then
            print '(a, i0, a, i0, a)', 'seed ', seed, ': ', problems, ' problems'
            failures = failures + 1
        end if
        call list%destroy()
    end subroutine

    !> Three atoms on a line in a box of zeros (a molecule needs no cell): the nearest neighbour
    !> of each (max_neighbors=1), then with the symmetric rule (atom 1 gains atom 2).
    subroutine nearest_in_a_molecule()
        type(tricell_neighbor_list) :: list
        real(c_double) :: x(3, 3), box(3, 3)
        integer :: status

        x = reshape([0d0, 0d0, 0d0, 1d0, 0d0, 0d0, 2.5d0, 0d0, 0d0], [3, 3])
        box = 0
        list = tricell_neighbor_list(10d0, max_neighbors=1)
        call list%compute(x, box, [.false., .false., .false.], status)
        call expect(status == TRICELL_OK, 'a molecule with a zero box')
        if (status /= TRICELL_OK) return
        call expect(list%npairs == 3, 'one neighbour each')
        call expect(all(list%j == [1, 0, 1]), 'the nearest of each')
        call expect(all(list%offsets == [0, 1, 2, 3]), 'offsets of the nearest')
        call list%destroy()
        list = tricell_neighbor_list(10d0, max_neighbors=1, symmetric=.true.)
        call list%compute(x, box, [.false., .false., .false.], status)
        call expect(status == TRICELL_OK .and. list%npairs == 4, 'the symmetric rule adds 1-2')
        if (status /= TRICELL_OK) return
        call expect(all(list%j == [1, 0, 2, 1]), 'atom 1: 0 at 1, then 2 at 1.5')
        call expect(all(list%offsets == [0, 1, 3, 4]), 'offsets of the symmetric nearest')
        call list%destroy()
    end subroutine

    !> Along random trajectories the Verlet list holds, at every step, exactly the pairs of a
    !> fresh sorted neighbour list (the same (i, j, S) per atom, any order within an atom).
    subroutine verlet_trajectories(count)
        integer, intent(in) :: count
        type(tricell_verlet_list) :: verlet
        type(tricell_neighbor_list) :: list
        real(c_double) :: box(3, 3), x(3, 30), steps(3, 30), cutoff
        logical :: rebuilt, periodic(3)
        integer :: system, t, status, k, m, a, rebuilds, updates
        logical :: found

        rebuilds = 0
        updates = 0
        do system = 1, count
            box = reshape([6d0, 0d0, 0d0, 1.5d0, 5.5d0, 0d0, -1d0, 0.8d0, 7d0], [3, 3])
            periodic = [.true., mod(system, 2) == 0, .true.]
            call random_number(x)
            x = matmul(box, x)
            cutoff = 2.5d0 + 0.1d0 * system
            verlet = tricell_verlet_list(cutoff, 0.4d0, half=mod(system, 3) == 0)
            list = tricell_neighbor_list(cutoff, half=mod(system, 3) == 0, sorted=.true.)
            do t = 1, 12
                call random_number(steps)
                x = x + 0.06d0 * (steps - 0.5d0)
                call verlet%update(x, box, periodic, rebuilt, status)
                call expect(status == TRICELL_OK, 'a Verlet update')
                call list%compute(x, box, periodic, status)
                call expect(status == TRICELL_OK, 'a neighbour list')
                if (status /= TRICELL_OK) return
                updates = updates + 1
                if (rebuilt) rebuilds = rebuilds + 1
                call expect(verlet%npairs == list%npairs, 'as many Verlet pairs as neighbours')
                call expect(associated(verlet%offsets), 'Verlet offsets')
                do k = 1, verlet%npairs
                    a = verlet%i(k)
                    found = .false.
                    do m = int(list%offsets(a)) + 1, int(list%offsets(a + 1))
                        if (list%j(m) == verlet%j(k) .and. &
                            all(list%shifts(:, m) == verlet%shifts(:, k))) found = .true.
                    end do
                    if (.not. found) then
                        call expect(.false., 'a Verlet pair the neighbour list does not have')
                        exit
                    end if
                end do
            end do
            call verlet%destroy()
            call list%destroy()
        end do
        call expect(rebuilds < updates .and. rebuilds >= count, 'some updates only refresh')
    end subroutine

    !> D = x_j - x_i + H S with 0-based i, j; d = |D| < cutoff; offsets delimit each atom's pairs.
    integer function check_in_fortran(list, x, box, cutoff, sorted) result(problems)
        type(tricell_neighbor_list), intent(in) :: list
        real(c_double), intent(in) :: x(:, :), box(3, 3), cutoff
        logical, intent(in) :: sorted
        real(c_double) :: d(3), scale
        integer :: k, a

        problems = 0
        scale = 1
        if (size(x, 2) > 0) scale = max(1d0, maxval(abs(x)))
        do k = 1, list%npairs
            d = x(:, list%j(k) + 1) - x(:, list%i(k) + 1) &
                + matmul(box, real(list%shifts(:, k), c_double))
            if (norm2(d - list%vectors(:, k)) > 1d-10 * scale) problems = problems + 1
            if (abs(norm2(d) - list%distances(k)) > 1d-10 * scale) problems = problems + 1
            if (.not. list%distances(k) < cutoff) problems = problems + 1
        end do
        if (sorted) then
            if (.not. associated(list%offsets)) then
                problems = problems + 1
                return
            end if
            if (lbound(list%offsets, 1) /= 0 .or. ubound(list%offsets, 1) /= size(x, 2)) &
                problems = problems + 1
            if (list%offsets(size(x, 2)) /= list%npairs) problems = problems + 1
            do a = 0, size(x, 2) - 1
                do k = int(list%offsets(a)) + 1, int(list%offsets(a + 1))
                    if (list%i(k) /= a) problems = problems + 1
                end do
            end do
        else if (associated(list%offsets)) then
            problems = problems + 1
        end if
    end function

    function perpendicular_widths(box) result(w)
        real(c_double), intent(in) :: box(3, 3)
        real(c_double) :: w(3), n(3)
        integer :: k
        do k = 1, 3
            n = cross(box(:, mod(k, 3) + 1), box(:, mod(k + 1, 3) + 1))
            w(k) = abs(dot_product(box(:, k), n)) / norm2(n)
        end do
    end function

    function cross(p, q) result(r)
        real(c_double), intent(in) :: p(3), q(3)
        real(c_double) :: r(3)
        r = [p(2) * q(3) - p(3) * q(2), p(3) * q(1) - p(1) * q(3), p(1) * q(2) - p(2) * q(1)]
    end function

    subroutine expect(condition, what)
        logical, intent(in) :: condition
        character(len=*), intent(in) :: what
        if (.not. condition) then
            print '(3a)', what, '; errmsg: ', tricell_errmsg()
            failures = failures + 1
        end if
    end subroutine

    subroutine error_paths()
        type(tricell_neighbor_list) :: list
        type(tricell_verlet_list) :: verlet
        logical :: rebuilt
        real(c_double) :: box(3, 3), x(3, 2), wide(4, 2)
        integer :: status

        box = 0
        box(1, 1) = 4
        box(2, 2) = 4
        box(3, 3) = 4
        x = reshape([0.5d0, 0.5d0, 0.5d0, 1.5d0, 0.5d0, 0.5d0], [3, 2])
        wide = 0

        list = tricell_neighbor_list(-1.5d0)
        call list%compute(x, box, [.true., .true., .true.], status)
        call expect(status == TRICELL_ERROR_INVALID_ARGUMENT, 'a bad cutoff is an invalid argument')
        call expect(tricell_errmsg() == 'cutoff must be > 0 (got -1.5)', 'the C++ message')
        call expect(list%npairs == 0 .and. .not. associated(list%i), 'an empty list on failure')
        call list%destroy()

        list = tricell_neighbor_list(1.5d0, sorted=.true.)
        call list%compute(wide, box, [.true., .true., .true.], status)
        call expect(status == TRICELL_ERROR_INVALID_ARGUMENT, 'positions(4, N) is refused')
        call expect(tricell_errmsg() == 'positions must have 3 rows, positions(3, N) (got 4)', &
                    'the shape message')
        call list%destroy()
        list = tricell_neighbor_list(0d0)
        call list%compute(x, box, [.true., .true., .true.], status, radii=[1d0])
        call expect(status == TRICELL_ERROR_INVALID_ARGUMENT, 'radii(1) for 2 atoms is refused')
        call expect(tricell_errmsg() == 'radii has 1 entries for 2 positions', 'the radii message')
        call list%compute(x, box, [.true., .true., .true.], status, radii=[1d0, -1d0])
        call expect(status == TRICELL_ERROR_INVALID_ARGUMENT, 'a negative radius is refused')
        call expect(tricell_errmsg() == 'radii[1] must be finite and >= 0 (got -1)', &
                    'the C++ radii message')
        call list%compute(x, box, [.true., .true., .true.], status, radii=[0.6d0, 0.6d0])
        call expect(status == TRICELL_OK .and. list%npairs == 2, 'radii 0.6 + 0.6 > 1: one pair')
        call list%destroy()
        list = tricell_neighbor_list(1.5d0, sorted=.true.)
        box(:, 2) = box(:, 1)
        call list%compute(x, box, [.true., .true., .true.], status)
        call expect(status == TRICELL_ERROR_GEOMETRY, 'a singular box is a geometry error')
        call expect(index(tricell_errmsg(), 'singular') > 0 .or. index(tricell_errmsg(), 'flat') > 0, &
                    'the singular-box message')
        box(:, 2) = [0d0, 4d0, 0d0]
        call list%compute(x, box, [.true., .false., .true.], status)
        call expect(status == TRICELL_OK, 'a good call after failures')
        call expect(tricell_errmsg() == '', 'a success clears the message')
        call expect(list%npairs == 2 .and. list%i(1) == 0 .and. list%j(1) == 1, 'one pair each way')
        call expect(size(list%offsets) == 3, 'offsets(0:N)')
        call expect(index(tricell_version(), '.') > 0, 'a version MAJOR.MINOR.PATCH')
        call list%destroy()
        call list%destroy() ! twice is harmless

        verlet = tricell_verlet_list(1.5d0, -1d0)
        call verlet%update(x, box, [.true., .true., .true.], rebuilt, status)
        call expect(status == TRICELL_ERROR_INVALID_ARGUMENT, 'a negative skin is refused')
        call expect(tricell_errmsg() == 'skin must be >= 0 (got -1)', 'the C++ skin message')
        call expect(.not. rebuilt .and. verlet%npairs == 0, 'nothing on failure')
        call verlet%destroy()
        verlet = tricell_verlet_list(1.5d0, 0.2d0)
        call verlet%update(wide, box, [.true., .true., .true.], rebuilt, status)
        call expect(status == TRICELL_ERROR_INVALID_ARGUMENT, 'Verlet positions(4, N) refused')
        call verlet%update(x, box, [.true., .true., .true.], rebuilt, status)
        call expect(status == TRICELL_OK .and. rebuilt .and. verlet%npairs == 2, 'a Verlet list')
        call verlet%destroy()
    end subroutine

end program
