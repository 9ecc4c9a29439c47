!> The Fortran 2008 module of tricell: neighbour lists through the C API (tricell.h) over
!> iso_c_binding, with the same semantics (docs/contract.md, bindings).
!>
!> Layout: positions are positions(3, N) (column k is atom k-1); the box is box(3, 3) with the
!> lattice vectors a, b, c as its COLUMNS; periodic(3) says which axes are periodic. Both arrays
!> have the memory layout the C API expects, so they are passed without a copy. Atom indices in
!> the results are 0-BASED, as everywhere in tricell: atom i is positions(:, i + 1). Results are
!> pointers into the C list's arrays (no copy), valid until the next compute() or destroy():
!> i(k), j(k), shifts(:, k), distances(k), vectors(:, k) for pair k = 1 .. npairs, and with
!> sorted or grouped output offsets(0:N), pairs of atom a being offsets(a) + 1 .. offsets(a + 1).
module tricell
    use, intrinsic :: iso_c_binding
    implicit none
    private

    public :: tricell_pair_arrays, tricell_neighbor_list, tricell_verlet_list
    public :: tricell_errmsg, tricell_version

    integer, parameter, public :: TRICELL_OK = 0
    integer, parameter, public :: TRICELL_ERROR_INVALID_ARGUMENT = 1
    integer, parameter, public :: TRICELL_ERROR_GEOMETRY = 2
    integer, parameter, public :: TRICELL_ERROR_OUT_OF_MEMORY = 3
    integer, parameter, public :: TRICELL_ERROR_INTERNAL = 4

    ! Search backends (tricell_backend): the result never depends on the choice.
    integer, parameter, public :: TRICELL_BACKEND_AUTOMATIC = 0
    integer, parameter, public :: TRICELL_BACKEND_DENSE = 1
    integer, parameter, public :: TRICELL_BACKEND_LINKED = 2
    integer, parameter, public :: TRICELL_BACKEND_HASH = 3
    integer, parameter, public :: TRICELL_BACKEND_OCTREE = 4
    integer, parameter, public :: TRICELL_BACKEND_DIRECT = 5

    ! The C structs of tricell.h, field for field.
    type, bind(c) :: c_box
        real(c_double) :: vectors(3, 3)
        integer(c_int) :: periodic(3)
    end type

    type, bind(c) :: c_neighbor_options
        real(c_double) :: cutoff
        integer(c_int) :: half, sorted, grouped, shifts, distances, vectors, threads, backend
        integer(c_size_t) :: max_pairs, max_bytes
        type(c_ptr) :: radii, species, species_cutoffs
        integer(c_size_t) :: species_cutoff_count
        type(c_ptr) :: query
        integer(c_size_t) :: query_count
        integer(c_size_t) :: max_neighbors
        real(c_double) :: tie_tolerance
        integer(c_int) :: symmetric
    end type

    type, bind(c) :: c_verlet_options
        type(c_neighbor_options) :: neighbors
        real(c_double) :: skin
    end type

    type, bind(c) :: c_species_cutoff
        integer(c_int32_t) :: a, b
        real(c_double) :: cutoff
    end type

    type, bind(c) :: c_pairs
        integer(c_size_t) :: size
        type(c_ptr) :: i, j, shifts, distances, vectors
        integer(c_size_t) :: atoms
        type(c_ptr) :: offsets
    end type

    !> The pairs of the last call: pointers into the C list's arrays, valid until the next call
    !> or destroy(). A quantity not asked for is a null pointer.
    type :: tricell_pair_arrays
        integer :: npairs = 0
        integer(c_int32_t), pointer, contiguous :: i(:) => null()
        integer(c_int32_t), pointer, contiguous :: j(:) => null()
        integer(c_int32_t), pointer, contiguous :: shifts(:, :) => null()
        real(c_double), pointer, contiguous :: distances(:) => null()
        real(c_double), pointer, contiguous :: vectors(:, :) => null()
        integer(c_size_t), pointer, contiguous :: offsets(:) => null()
    end type

    !> A neighbour list: options from the constructor, buffers kept between compute() calls.
    !> Call destroy() when done (the type has no finalizer, so copies never free twice).
    type, extends(tricell_pair_arrays) :: tricell_neighbor_list
        type(c_neighbor_options), private :: options
        type(c_species_cutoff), pointer, contiguous, private :: table(:) => null()
        type(c_ptr), private :: search = c_null_ptr
        type(c_ptr), private :: list = c_null_ptr
    contains
        procedure :: compute
        procedure :: destroy
    end type

    !> A Verlet list: candidates at cutoff + skin, refreshed by every update(), rebuilt only
    !> when atoms moved too far. Pairs grouped by i (offsets(0:N) always set). Call destroy().
    type, extends(tricell_pair_arrays) :: tricell_verlet_list
        type(c_verlet_options), private :: options
        type(c_ptr), private :: verlet = c_null_ptr
    contains
        procedure :: update => verlet_update
        procedure :: destroy => verlet_destroy
    end type

    interface tricell_verlet_list
        module procedure new_verlet_list
    end interface

    interface tricell_neighbor_list
        module procedure new_neighbor_list
    end interface

    interface
        function c_last_error() bind(c, name="tricell_last_error")
            import :: c_ptr
            type(c_ptr) :: c_last_error
        end function
        function c_version() bind(c, name="tricell_version")
            import :: c_ptr
            type(c_ptr) :: c_version
        end function
        function c_box_from_rows(rows, periodic, box) bind(c, name="tricell_box_from_rows")
            import :: c_int, c_double, c_box
            real(c_double), intent(in) :: rows(*)
            integer(c_int), intent(in) :: periodic(3)
            type(c_box), intent(out) :: box
            integer(c_int) :: c_box_from_rows
        end function
        function c_neighbor_options_init(options) bind(c, name="tricell_neighbor_options_init")
            import :: c_int, c_neighbor_options
            type(c_neighbor_options), intent(out) :: options
            integer(c_int) :: c_neighbor_options_init
        end function
        function c_neighbor_search_create(search) bind(c, name="tricell_neighbor_search_create")
            import :: c_int, c_ptr
            type(c_ptr), intent(out) :: search
            integer(c_int) :: c_neighbor_search_create
        end function
        subroutine c_neighbor_search_destroy(search) bind(c, name="tricell_neighbor_search_destroy")
            import :: c_ptr
            type(c_ptr), value :: search
        end subroutine
        function c_neighbor_list_create(list) bind(c, name="tricell_neighbor_list_create")
            import :: c_int, c_ptr
            type(c_ptr), intent(out) :: list
            integer(c_int) :: c_neighbor_list_create
        end function
        subroutine c_neighbor_list_destroy(list) bind(c, name="tricell_neighbor_list_destroy")
            import :: c_ptr
            type(c_ptr), value :: list
        end subroutine
        function c_neighbors(search, box, positions, n, options, list) &
                bind(c, name="tricell_neighbors")
            import :: c_int, c_ptr, c_double, c_size_t, c_box, c_neighbor_options
            type(c_ptr), value :: search, list
            type(c_box), intent(in) :: box
            real(c_double), intent(in) :: positions(*)
            integer(c_size_t), value :: n
            type(c_neighbor_options), intent(in) :: options
            integer(c_int) :: c_neighbors
        end function
        function c_neighbor_list_pairs(list, pairs) bind(c, name="tricell_neighbor_list_pairs")
            import :: c_int, c_ptr, c_pairs
            type(c_ptr), value :: list
            type(c_pairs), intent(out) :: pairs
            integer(c_int) :: c_neighbor_list_pairs
        end function
        function c_verlet_options_init(options) bind(c, name="tricell_verlet_options_init")
            import :: c_int, c_verlet_options
            type(c_verlet_options), intent(out) :: options
            integer(c_int) :: c_verlet_options_init
        end function
        function c_verlet_create(options, verlet) bind(c, name="tricell_verlet_create")
            import :: c_int, c_ptr, c_verlet_options
            type(c_verlet_options), intent(in) :: options
            type(c_ptr), intent(out) :: verlet
            integer(c_int) :: c_verlet_create
        end function
        subroutine c_verlet_destroy(verlet) bind(c, name="tricell_verlet_destroy")
            import :: c_ptr
            type(c_ptr), value :: verlet
        end subroutine
        function c_verlet_update(verlet, box, positions, n, rebuilt) &
                bind(c, name="tricell_verlet_update")
            import :: c_int, c_ptr, c_double, c_size_t, c_box
            type(c_ptr), value :: verlet
            type(c_box), intent(in) :: box
            real(c_double), intent(in) :: positions(*)
            integer(c_size_t), value :: n
            integer(c_int), intent(out) :: rebuilt
            integer(c_int) :: c_verlet_update
        end function
        function c_verlet_pairs(verlet, pairs) bind(c, name="tricell_verlet_pairs")
            import :: c_int, c_ptr, c_pairs
            type(c_ptr), value :: verlet
            type(c_pairs), intent(out) :: pairs
            integer(c_int) :: c_verlet_pairs
        end function
        function c_strlen(s) bind(c, name="strlen")
            import :: c_ptr, c_size_t
            type(c_ptr), value :: s
            integer(c_size_t) :: c_strlen
        end function
    end interface

    ! A message from the Fortran side's own checks (array shapes), which the C API never sees;
    ! empty when the last failure came from the C API.
    character(len=:), allocatable, save :: fortran_error
    !$omp threadprivate(fortran_error)

contains

    !> A neighbour list for pairs closer than `cutoff` (strict). Optional: half (each pair once),
    !> sorted (by i, j, S, with offsets), grouped (by i in the search's order, with offsets),
    !> shifts and distances (stored unless .false.), vectors
    !> (stored if .true.), threads (default 1, 0 = all cores), backend (TRICELL_BACKEND_*), and a
    !> per-species cutoff table: species_pairs(:, k) = [a, b] with species_cutoffs(k) (then
    !> cutoff is 0 and compute() takes species); max_neighbors (the k nearest within the cutoff,
    !> each atom's pairs by distance with offsets), tie_tolerance and symmetric as in the C API.
    !> Options are checked by compute().
    function new_neighbor_list(cutoff, half, sorted, shifts, distances, vectors, threads, &
                               backend, species_pairs, species_cutoffs, grouped, max_neighbors, &
                               tie_tolerance, symmetric) result(self)
        real(c_double), intent(in) :: cutoff
        logical, intent(in), optional :: half, sorted, shifts, distances, vectors, grouped
        logical, intent(in), optional :: symmetric
        integer, intent(in), optional :: threads, backend, max_neighbors
        real(c_double), intent(in), optional :: tie_tolerance
        integer, intent(in), optional :: species_pairs(:, :)
        real(c_double), intent(in), optional :: species_cutoffs(:)
        type(tricell_neighbor_list) :: self
        integer(c_int) :: status
        integer :: k

        status = c_neighbor_options_init(self%options)
        self%options%cutoff = cutoff
        if (present(half)) self%options%half = merge(1, 0, half)
        if (present(sorted)) self%options%sorted = merge(1, 0, sorted)
        if (present(grouped)) self%options%grouped = merge(1, 0, grouped)
        if (present(shifts)) self%options%shifts = merge(1, 0, shifts)
        if (present(distances)) self%options%distances = merge(1, 0, distances)
        if (present(vectors)) self%options%vectors = merge(1, 0, vectors)
        if (present(threads)) self%options%threads = int(threads, c_int)
        if (present(backend)) self%options%backend = int(backend, c_int)
        if (present(max_neighbors)) self%options%max_neighbors = int(max_neighbors, c_size_t)
        if (present(tie_tolerance)) self%options%tie_tolerance = tie_tolerance
        if (present(symmetric)) self%options%symmetric = merge(1, 0, symmetric)
        if (present(species_pairs) .and. present(species_cutoffs)) then
            allocate (self%table(min(size(species_pairs, 2), size(species_cutoffs))))
            do k = 1, size(self%table)
                self%table(k) = c_species_cutoff(int(species_pairs(1, k), c_int32_t), &
                                                 int(species_pairs(2, k), c_int32_t), &
                                                 species_cutoffs(k))
            end do
        end if
    end function

    !> Finds the pairs of positions(3, N) in the box with lattice vectors box(:, 1), box(:, 2),
    !> box(:, 3) and periodicity periodic(3). status is TRICELL_OK (0) or an error code; then
    !> tricell_errmsg() says what is wrong and the list is empty. Variable cutoffs: radii(N)
    !> (a pair counts when d < r_i + r_j; construct with cutoff 0), or species(N) with the
    !> constructor's species table.
    subroutine compute(self, positions, box, periodic, status, radii, species)
        class(tricell_neighbor_list), intent(inout) :: self
        real(c_double), intent(in), contiguous :: positions(:, :)
        real(c_double), intent(in) :: box(3, 3)
        logical, intent(in) :: periodic(3)
        integer, intent(out) :: status
        real(c_double), intent(in), optional, target, contiguous :: radii(:)
        integer(c_int32_t), intent(in), optional, target, contiguous :: species(:)
        type(c_box) :: cbox
        type(c_pairs) :: pairs
        type(c_neighbor_options) :: options
        integer(c_int) :: pbc(3)

        call clear_results(self)
        fortran_error = ''
        if (size(positions, 1) /= 3) then
            fortran_error = 'positions must have 3 rows, positions(3, N) (got ' &
                            // itoa(size(positions, 1)) // ')'
            status = TRICELL_ERROR_INVALID_ARGUMENT
            return
        end if
        options = self%options
        if (present(radii)) then
            if (size(radii) /= size(positions, 2)) then
                fortran_error = 'radii has ' // itoa(size(radii)) // ' entries for ' &
                                // itoa(size(positions, 2)) // ' positions'
                status = TRICELL_ERROR_INVALID_ARGUMENT
                return
            end if
            if (size(radii) > 0) options%radii = c_loc(radii)
        end if
        if (present(species)) then
            if (size(species) /= size(positions, 2)) then
                fortran_error = 'species has ' // itoa(size(species)) // ' entries for ' &
                                // itoa(size(positions, 2)) // ' positions'
                status = TRICELL_ERROR_INVALID_ARGUMENT
                return
            end if
            if (size(species) > 0) options%species = c_loc(species)
        end if
        if (associated(self%table)) then
            if (size(self%table) > 0) then
                options%species_cutoffs = c_loc(self%table)
                options%species_cutoff_count = size(self%table, kind=c_size_t)
            end if
        end if
        if (.not. c_associated(self%search)) then
            status = c_neighbor_search_create(self%search)
            if (status /= TRICELL_OK) return
        end if
        if (.not. c_associated(self%list)) then
            status = c_neighbor_list_create(self%list)
            if (status /= TRICELL_OK) return
        end if
        pbc = merge(1, 0, periodic)
        ! box(3, 3) by columns is, in memory, the lattice vectors one after the other: rows in C.
        status = c_box_from_rows(box, pbc, cbox)
        if (status /= TRICELL_OK) return
        status = c_neighbors(self%search, cbox, positions, int(size(positions, 2), c_size_t), &
                             options, self%list)
        if (status /= TRICELL_OK) return
        status = c_neighbor_list_pairs(self%list, pairs)
        if (status /= TRICELL_OK) return
        call view_pairs(self, pairs)
    end subroutine

    !> Frees the C handles; the object can be used again afterwards (it recreates them).
    subroutine destroy(self)
        class(tricell_neighbor_list), intent(inout) :: self
        call clear_results(self)
        if (associated(self%table)) deallocate (self%table)
        call c_neighbor_search_destroy(self%search)
        call c_neighbor_list_destroy(self%list)
        self%search = c_null_ptr
        self%list = c_null_ptr
    end subroutine

    !> A Verlet list for pairs closer than `cutoff` after every update(), candidates built at
    !> cutoff + skin. Optional: half, shifts, distances, vectors, threads, backend as for
    !> tricell_neighbor_list. Options are checked by the first update().
    function new_verlet_list(cutoff, skin, half, shifts, distances, vectors, threads, backend) &
            result(self)
        real(c_double), intent(in) :: cutoff, skin
        logical, intent(in), optional :: half, shifts, distances, vectors
        integer, intent(in), optional :: threads, backend
        type(tricell_verlet_list) :: self
        integer(c_int) :: status

        status = c_verlet_options_init(self%options)
        self%options%neighbors%cutoff = cutoff
        self%options%skin = skin
        if (present(half)) self%options%neighbors%half = merge(1, 0, half)
        if (present(shifts)) self%options%neighbors%shifts = merge(1, 0, shifts)
        if (present(distances)) self%options%neighbors%distances = merge(1, 0, distances)
        if (present(vectors)) self%options%neighbors%vectors = merge(1, 0, vectors)
        if (present(threads)) self%options%neighbors%threads = int(threads, c_int)
        if (present(backend)) self%options%neighbors%backend = int(backend, c_int)
    end function

    !> The pairs within the cutoff for positions(3, N) in box(3, 3) (vectors as columns) with
    !> periodic(3); rebuilt is .true. when the candidates were rebuilt. On failure (status not
    !> TRICELL_OK, see tricell_errmsg()) the list is empty and the next update rebuilds.
    subroutine verlet_update(self, positions, box, periodic, rebuilt, status)
        class(tricell_verlet_list), intent(inout) :: self
        real(c_double), intent(in), contiguous :: positions(:, :)
        real(c_double), intent(in) :: box(3, 3)
        logical, intent(in) :: periodic(3)
        logical, intent(out) :: rebuilt
        integer, intent(out) :: status
        type(c_box) :: cbox
        type(c_pairs) :: pairs
        integer(c_int) :: c_rebuilt

        call clear_results(self)
        rebuilt = .false.
        fortran_error = ''
        if (size(positions, 1) /= 3) then
            fortran_error = 'positions must have 3 rows, positions(3, N) (got ' &
                            // itoa(size(positions, 1)) // ')'
            status = TRICELL_ERROR_INVALID_ARGUMENT
            return
        end if
        if (.not. c_associated(self%verlet)) then
            status = c_verlet_create(self%options, self%verlet)
            if (status /= TRICELL_OK) return
        end if
        status = c_box_from_rows(box, merge(1, 0, periodic), cbox)
        if (status /= TRICELL_OK) return
        status = c_verlet_update(self%verlet, cbox, positions, int(size(positions, 2), c_size_t), &
                                 c_rebuilt)
        if (status /= TRICELL_OK) return
        rebuilt = c_rebuilt == 1
        status = c_verlet_pairs(self%verlet, pairs)
        if (status /= TRICELL_OK) return
        call view_pairs(self, pairs)
    end subroutine

    subroutine verlet_destroy(self)
        class(tricell_verlet_list), intent(inout) :: self
        call clear_results(self)
        call c_verlet_destroy(self%verlet)
        self%verlet = c_null_ptr
    end subroutine

    !> The message of this thread's last failed call ('' after a successful one).
    function tricell_errmsg() result(message)
        character(len=:), allocatable :: message
        if (allocated(fortran_error)) then
            if (len(fortran_error) > 0) then
                message = fortran_error
                return
            end if
        end if
        message = c_string(c_last_error())
    end function

    !> The library's version, "MAJOR.MINOR.PATCH".
    function tricell_version() result(version)
        character(len=:), allocatable :: version
        version = c_string(c_version())
    end function

    subroutine clear_results(self)
        class(tricell_pair_arrays), intent(inout) :: self
        self%npairs = 0
        nullify (self%i, self%j, self%shifts, self%distances, self%vectors, self%offsets)
    end subroutine

    subroutine view_pairs(self, pairs)
        class(tricell_pair_arrays), intent(inout) :: self
        type(c_pairs), intent(in) :: pairs
        integer(c_size_t), pointer, contiguous :: offsets(:)
        integer :: n

        n = int(pairs%size)
        self%npairs = n
        call c_f_pointer(pairs%i, self%i, [n])
        call c_f_pointer(pairs%j, self%j, [n])
        if (c_associated(pairs%shifts)) call c_f_pointer(pairs%shifts, self%shifts, [3, n])
        if (c_associated(pairs%distances)) call c_f_pointer(pairs%distances, self%distances, [n])
        if (c_associated(pairs%vectors)) call c_f_pointer(pairs%vectors, self%vectors, [3, n])
        if (c_associated(pairs%offsets)) then
            call c_f_pointer(pairs%offsets, offsets, [pairs%atoms + 1])
            self%offsets(0:) => offsets
        end if
    end subroutine

    function c_string(p) result(s)
        type(c_ptr), intent(in) :: p
        character(len=:), allocatable :: s
        character(kind=c_char), pointer :: chars(:)
        integer :: k, n

        n = int(c_strlen(p))
        call c_f_pointer(p, chars, [n])
        allocate (character(len=n) :: s)
        do k = 1, n
            s(k:k) = chars(k)
        end do
    end function

    function itoa(v) result(s)
        integer, intent(in) :: v
        character(len=:), allocatable :: s
        character(len=24) :: buffer
        write (buffer, '(i0)') v
        s = trim(buffer)
    end function

end module tricell
