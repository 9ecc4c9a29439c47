"""Hostile array arguments, generated: every array argument of every function of the native
module (and of the ASE and pymatgen drop-ins) gets every dtype numpy has (each kind b i u f c m
M O S U V, both byte orders), wrong shapes (rank, width, count, empty, a 0-d scalar, ragged
lists), array-likes (lists, tuples, lists mixing numbers with None or str) and memory layouts
(Fortran order, strided and negative-stride views, read-only, non-contiguous column views).

Each case must either give exactly the result of the same values passed as a C-contiguous
float64 array (int64 for species, bool for periodicity), or raise TypeError or ValueError whose
message names the argument: never another exception, never a different answer. Accepted: real
kinds (f, i, u) for positions, boxes and radii; integers, and floats holding whole numbers, for
species; bools and the integers 0 and 1 for periodicity. Everything else is refused.

Batches are walked both as sequences of arrays and as one (S, N, 3), (S, 3, 3) or (S, 3) array.

`python3 test_hostile_arguments.py` prints how many cases gave each outcome."""
import collections
import types

import numpy as np
import pytest

import tricell
import tricell.ase
import tricell.pymatgen

RNG = np.random.default_rng(20261203)
ATOMS = 8
POINTS = RNG.uniform(0.0, 4.0, (ATOMS, 3))
BOX = np.array([[4.2, 0.0, 0.0], [1.3, 4.5, 0.0], [0.7, 0.9, 4.8]])
PERIODIC = np.array([True, True, True])
RADII = RNG.uniform(0.3, 1.2, ATOMS)
SPECIES = RNG.integers(1, 3, ATOMS)
TABLE = {(1, 1): 1.5, (1, 2): 2.0, (2, 2): 2.5}

# What each rule accepts and what a clean input of it is.
ACCEPTS = {"real": "fiu", "species": "fiu", "periodic": "biu", "index": "iu"}
CANONICAL = {"real": np.float64, "species": np.int64, "periodic": np.bool_, "index": np.int64}


def every_dtype():
    """Every scalar type numpy has, with the swapped byte order of each multi-byte one, plus
    unit-carrying datetimes, sized strings and a structured record."""
    dtypes = {np.dtype(t) for t in set(np.sctypeDict.values())}
    dtypes |= {np.dtype(d) for d in ("M8[s]", "m8[ns]", "S8", "U8", "V8", [("x", "<f8")])}
    dtypes = sorted(dtypes, key=str)
    swapped = [d.newbyteorder("S") for d in dtypes
               if d.kind in "iufcmM" and d.itemsize > 1]
    return dtypes + swapped


DTYPES = every_dtype()


def as_dtype(value, dtype):
    """value in dtype: a cast where numpy has one, else values of that dtype of the same shape."""
    if dtype.kind in "mM":
        return np.asarray(value).astype(np.int64).astype(dtype)
    if dtype.kind == "V":
        return np.zeros(np.shape(value), dtype)
    if dtype.kind in "SU":
        return np.asarray(value).astype(dtype)
    return np.asarray(value).astype(dtype)


def layouts(value):
    """The same values in other memory layouts: (label, array)."""
    out = [("C", value)]
    fortran = np.asfortranarray(value)
    out.append(("Fortran", fortran))
    if value.ndim >= 1:
        wide = np.zeros((value.shape[0] * 2,) + value.shape[1:], value.dtype)
        wide[::2] = value
        out.append(("every other row", wide[::2]))
        backwards = value[::-1].copy()
        out.append(("negative stride", backwards[::-1]))
    if value.ndim >= 2:
        columns = np.zeros(value.shape[:-1] + (value.shape[-1] * 3,), value.dtype)
        columns[..., 1::3] = value
        out.append(("column view", columns[..., 1::3]))
        out.append(("transposed twice", value.T.copy().T))
        every = tuple(slice(None, None, -2) for _ in value.shape)
        both = np.zeros(tuple(2 * n for n in value.shape), value.dtype)[every]
        both[...] = value
        out.append(("negative strides on every axis", both))
    frozen = value.copy()
    frozen.flags.writeable = False
    out.append(("read-only", frozen))
    return out


def wrong_shapes(value, rule, name):
    """(label, array) of shapes the argument refuses (a 0-d periodic is every axis, a 0-d ASE
    cutoff one cutoff for all)."""
    scalar = rule != "periodic" and name != "cutoff"
    out = [("0-d scalar", np.asarray(value).reshape(-1)[0])] if scalar else []
    out.append(("one more axis", value[None]))
    if value.ndim == 3:  # one array of structures
        return out + [("one column less", value[..., :-1]), ("one column more", value[..., :1]),
                      ("flattened structures", value.reshape(value.shape[0], -1))]
    if value.ndim == 2:
        out += [("one column less", value[:, :-1]),
                ("one column more", np.hstack([value, value[:, :1]])),
                ("flattened", value.reshape(-1)), ("empty of width 2", value[:0, :2])]
        if value.shape[0] == 3:
            out += [("two rows", value[:2]), ("four rows", np.vstack([value, value[:1]])),
                    ("empty", value[:0])]
    else:
        out += [("one entry less", value[:-1]),
                ("one entry more", np.concatenate([value, value[:1]])),
                ("empty", value[:0]), ("a column", value[:, None])]
    return out


def array_likes(value):
    """Lists and tuples: (label, object, outcome: "same" or the exception it must raise)."""
    rows = value.tolist()
    out = [("list", rows, "same"),
           ("tuple", tuple(tuple(r) if isinstance(r, list) else r for r in rows), "same")]
    if value.ndim == 2:
        out.append(("ragged list", [rows[0][:2]] + rows[1:], ValueError))
        out.append(("list with None", [[None] + rows[0][1:]] + rows[1:], TypeError))
        out.append(("list with a numeric str", [["1.0"] + rows[0][1:]] + rows[1:], TypeError))
    elif value.ndim == 3:  # one array of structures: the odd value in place of one number
        first = [[None] + rows[0][0][1:]] + rows[0][1:]
        out.append(("ragged list", [rows[:2]] + rows[2:], ValueError))
        out.append(("list with None", [first] + rows[1:], TypeError))
        first = [["1.0"] + rows[0][0][1:]] + rows[0][1:]
        out.append(("list with a numeric str", [first] + rows[1:], TypeError))
    else:
        out.append(("ragged list", [rows[:2]] + rows[2:], ValueError))
        out.append(("list with None", [None] + rows[1:], TypeError))
        out.append(("list with a numeric str", ["1"] + rows[1:], TypeError))
    return out


def results(value):
    """The outputs of a call as a tuple of arrays, for exact comparison."""
    if isinstance(value, np.ndarray):
        return (value,)
    if value is None:
        return ()
    return tuple(x for v in value for x in results(v))


def outcome(call, argument):
    """("result", arrays) or ("error", type, message); any other exception propagates."""
    try:
        return ("result", results(call(argument)))
    except (TypeError, ValueError) as e:
        return ("error", type(e), str(e))


def same(a, b):
    if a[0] != b[0]:
        return False
    if a[0] == "error":
        return a[1:] == b[1:]
    return len(a[1]) == len(b[1]) and all(
        x.dtype == y.dtype and x.shape == y.shape and np.array_equal(x, y, equal_nan=True)
        for x, y in zip(a[1], b[1]))


def rdf_total(points, box, periodic, species=None):
    rdf = tricell.Rdf(3.0, 12)
    rdf.add_frame(points, box, periodic, species)
    return rdf.total()


def fake_structure(coords, matrix, pbc):
    return types.SimpleNamespace(cart_coords=coords,
                                 lattice=types.SimpleNamespace(matrix=matrix, pbc=pbc))


P, B, Q = POINTS, BOX, PERIODIC
# (function, argument as named in messages, rule, clean value, call with the argument replaced)
CASES = [
    ("NeighborList.compute", "points", "real", P,
     lambda x: tricell.NeighborList(1.8).compute(x, B, Q, "ijSdD")),
    ("NeighborList.compute", "box", "real", B,
     lambda x: tricell.NeighborList(1.8).compute(P, x, Q, "ijSdD")),
    ("NeighborList.compute", "periodic", "periodic", Q,
     lambda x: tricell.NeighborList(1.8).compute(P, B, x, "ijSdD")),
    ("NeighborList.compute", "radii", "real", RADII,
     lambda x: tricell.NeighborList(None).compute(P, B, Q, "ijSd", radii=x)),
    ("NeighborList.compute", "species", "species", SPECIES,
     lambda x: tricell.NeighborList(TABLE).compute(P, B, Q, "ijSd", species=x)),
    ("NeighborList.compute_batch", "points", "real", P,
     lambda x: tricell.NeighborList(1.8).compute_batch([P, x], [B, B], Q, "ijSd")),
    ("NeighborList.compute_batch", "boxes", "real", B,
     lambda x: tricell.NeighborList(1.8).compute_batch([P, P], [B, x], Q, "ijSd")),
    ("NeighborList.compute_batch", "periodic", "periodic", Q,
     lambda x: tricell.NeighborList(1.8).compute_batch([P, P], [B, B], x, "ijSd")),
    ("NeighborList.compute_batch (S, N, 3)", "points", "real", np.stack([P, P[::-1]]),
     lambda x: tricell.NeighborList(1.8).compute_batch(x, [B, B], Q, "ijSd")),
    ("NeighborList.compute_batch (S, 3, 3)", "boxes", "real", np.stack([B, 1.1 * B]),
     lambda x: tricell.NeighborList(1.8).compute_batch([P, P], x, Q, "ijSd")),
    ("NeighborList.compute_batch (S, 3)", "periodic", "periodic", np.array([Q, [1, 0, 1]], bool),
     lambda x: tricell.NeighborList(1.8).compute_batch([P, P], [B, B], x, "ijSd")),
    ("NeighborList.compute_batch (batch_ptr)", "points", "real", np.vstack([P, P[::-1]]),
     lambda x: tricell.NeighborList(1.8).compute_batch(x, [B, B], Q, "ijSd",
                                                       batch_ptr=[0, ATOMS, 2 * ATOMS])),
    ("NeighborList.compute_batch (batch_ptr)", "boxes", "real", np.stack([B, 1.1 * B]),
     lambda x: tricell.NeighborList(1.8).compute_batch(np.vstack([P, P]), x, Q, "ijSd",
                                                       batch_ptr=[0, ATOMS, 2 * ATOMS])),
    ("NeighborList.compute_batch (batch_ptr)", "periodic", "periodic",
     np.array([Q, [1, 0, 1]], bool),
     lambda x: tricell.NeighborList(1.8).compute_batch(np.vstack([P, P]), [B, B], x, "ijSd",
                                                       batch_ptr=[0, ATOMS, 2 * ATOMS])),
    ("NeighborList.compute_batch (batch_ptr)", "batch_ptr", "index",
     np.array([0, 3, 2 * ATOMS]),
     lambda x: tricell.NeighborList(1.8).compute_batch(np.vstack([P, P]), [B, B], Q, "ijSd",
                                                       batch_ptr=x)),
    ("neighbor_shells", "points", "real", P,
     lambda x: tricell.neighbor_shells(x, B, Q, [1.0, 1.8], "ijSdD")),
    ("neighbor_shells", "box", "real", B,
     lambda x: tricell.neighbor_shells(P, x, Q, [1.0, 1.8], "ijSdD")),
    ("neighbor_shells", "periodic", "periodic", Q,
     lambda x: tricell.neighbor_shells(P, B, x, [1.0, 1.8], "ijSdD")),
    ("VerletList.update", "points", "real", P,
     lambda x: tricell.VerletList(1.8, 0.3).update(x, B, Q, "ijSd")),
    ("VerletList.update", "box", "real", B,
     lambda x: tricell.VerletList(1.8, 0.3).update(P, x, Q, "ijSd")),
    ("VerletList.update", "periodic", "periodic", Q,
     lambda x: tricell.VerletList(1.8, 0.3).update(P, B, x, "ijSd")),
    ("Rdf.add_frame", "points", "real", P, lambda x: rdf_total(x, B, Q)),
    ("Rdf.add_frame", "box", "real", B, lambda x: rdf_total(P, x, Q)),
    ("Rdf.add_frame", "periodic", "periodic", Q, lambda x: rdf_total(P, B, x)),
    ("Rdf.add_frame", "species", "species", SPECIES, lambda x: rdf_total(P, B, Q, x)),
    ("nearest_neighbors", "points", "real", P, lambda x: tricell.nearest_neighbors(x, B, Q, 2)),
    ("nearest_neighbors", "box", "real", B, lambda x: tricell.nearest_neighbors(P, x, Q, 2)),
    ("nearest_neighbors", "periodic", "periodic", Q,
     lambda x: tricell.nearest_neighbors(P, B, x, 2)),
    ("ase.primitive_neighbor_list", "positions", "real", P,
     lambda x: tricell.ase.primitive_neighbor_list("ijSd", Q, B, x, 1.8)),
    ("ase.primitive_neighbor_list", "cell", "real", B,
     lambda x: tricell.ase.primitive_neighbor_list("ijSd", Q, x, P, 1.8)),
    ("ase.primitive_neighbor_list", "pbc", "periodic", Q,
     lambda x: tricell.ase.primitive_neighbor_list("ijSd", x, B, P, 1.8)),
    ("ase.primitive_neighbor_list", "cutoff", "real", RADII,
     lambda x: tricell.ase.primitive_neighbor_list("ijSd", Q, B, P, x)),
    ("ase.primitive_neighbor_list", "numbers", "species", SPECIES,
     lambda x: tricell.ase.primitive_neighbor_list("ijSd", Q, B, P, TABLE, numbers=x)),
    ("pymatgen.get_neighbor_list", "structure.cart_coords", "real", P,
     lambda x: tricell.pymatgen.get_neighbor_list(fake_structure(x, B, Q), 1.8)),
    ("pymatgen.get_neighbor_list", "structure.lattice.matrix", "real", B,
     lambda x: tricell.pymatgen.get_neighbor_list(fake_structure(P, x, Q), 1.8)),
    ("pymatgen.get_neighbor_list", "structure.lattice.pbc", "periodic", Q,
     lambda x: tricell.pymatgen.get_neighbor_list(fake_structure(P, B, x), 1.8)),
]


def generated(rule, clean, name):
    """(label, argument, expectation): "same" (the result of the canonical array of the same
    values), TypeError, ValueError, or "refused" (TypeError or ValueError)."""
    for dtype in DTYPES:
        value = as_dtype(clean, dtype)
        accepted = dtype.kind in ACCEPTS[rule]
        for label, arranged in layouts(value):
            yield f"{dtype.str} {label}", arranged, "same" if accepted else TypeError
        for label, shaped in wrong_shapes(value, rule, name):
            yield f"{dtype.str} {label}", shaped, ValueError if accepted else "refused"
    for label, like, expected in array_likes(clean):
        yield label, like, expected
    if rule == "species":
        fractional = clean.astype(float)
        fractional[3] += 0.5
        yield "float with a fraction", fractional, ValueError
        for bad in (np.nan, np.inf, 2.0 ** 40):
            values = clean.astype(float)
            values[2] = bad
            yield f"float {bad}", values, ValueError
        values = clean.astype(np.uint64)
        values[1] = 2 ** 63 + 1
        yield "uint64 beyond int64", values, ValueError
    if rule == "periodic":
        yield "integer 2", np.array([1, 2, 1]), ValueError
        yield "Python True", True, "same"
        yield "numpy True", np.True_, "same"
        yield "Python 1", 1, "same"
        yield "None", None, TypeError


def canonical(rule, argument):
    return np.array(argument, dtype=CANONICAL[rule], order="C")


def check_family(case):
    """Runs every generated argument of one (function, argument); returns the tally of
    outcomes and the failures."""
    function, name, rule, clean, call = case
    tally = collections.Counter()
    failures = []
    for label, argument, expected in generated(rule, clean, name):
        where = f"{function} {name}={label}"
        try:
            got = outcome(call, argument)
        except Exception as e:  # noqa: BLE001 -- any other exception is a failure to report
            failures.append(f"{where}: {type(e).__name__}: {e}")
            continue
        if got[0] == "result":
            tally["result"] += 1
            if expected != "same":
                failures.append(f"{where}: gave a result, expected {expected}")
            elif not same(got, outcome(call, canonical(rule, argument))):
                failures.append(f"{where}: a result different from the float64 C-order input")
            continue
        kind, message = got[1], got[2]
        tally[kind.__name__] += 1
        if name not in message:
            failures.append(f"{where}: {kind.__name__} not naming {name}: {message}")
        elif expected == "same":
            reference = outcome(call, canonical(rule, argument))
            if not same(got, reference):
                failures.append(f"{where}: {kind.__name__}: {message} (float64 input: "
                                f"{reference[0]})")
        elif expected != "refused" and kind is not expected:
            failures.append(f"{where}: {kind.__name__}: {message}, expected {expected.__name__}")
    return tally, failures


@pytest.mark.parametrize("case", CASES, ids=[f"{c[0]}-{c[1]}" for c in CASES])
def test_hostile_arguments_give_the_result_or_an_error_naming_the_argument(case):
    tally, failures = check_family(case)
    assert sum(tally.values()) > 300
    assert not failures, f"{len(failures)} failures:\n" + "\n".join(failures[:40])


def test_the_messages_say_what_the_argument_got():
    nl = tricell.NeighborList(1.8)
    with pytest.raises(TypeError, match=r"^points must hold real numbers \(float or int\), not "
                                        r"complex \(got dtype complex128, shape \(8, 3\)\)$"):
        nl.compute(P + 1j, B)
    with pytest.raises(TypeError, match=r"box must hold real numbers .*not str \(got dtype <U"):
        nl.compute(P, B.astype(str))
    with pytest.raises(TypeError, match=r"points must hold real numbers .*not Python objects"):
        nl.compute(np.array([[1.0, "a", 2.0]], dtype=object), B)
    with pytest.raises(TypeError, match=r"periodic must be bools, not float \(got dtype float64, "
                                        r"shape \(3,\)\)"):
        nl.compute(P, B, np.ones(3))
    with pytest.raises(ValueError, match=r"points must be a rectangular array of numbers"):
        nl.compute([[0.0, 0.0, 0.0], [1.0, 1.0]], B)
    with pytest.raises(ValueError, match=r"species must be integers \(got species\[3\] = 1.5, "
                                         r"dtype float64\)"):
        tricell.NeighborList(TABLE).compute(P, B, species=[1, 1, 1, 1.5, 1, 1, 1, 1])
    with pytest.raises(TypeError, match=r"structure 1: points must hold real numbers"):
        nl.compute_batch([P, P.astype(complex)], [B, B])
    with pytest.raises(TypeError, match=r"cell must hold real numbers .*not complex"):
        tricell.ase.primitive_neighbor_list("ij", Q, B + 0j, P, 1.8)


def test_a_tensor_that_requires_grad_is_a_type_error_naming_the_argument():
    torch = pytest.importorskip("torch")
    x = torch.tensor(P, requires_grad=True)
    with pytest.raises(TypeError, match=r"points cannot be converted to a numpy array"):
        tricell.NeighborList(1.8).compute(x, B)
    same_values = tricell.NeighborList(1.8).compute(torch.tensor(P), torch.tensor(B))
    for mine, theirs in zip(same_values, tricell.NeighborList(1.8).compute(P, B)):
        np.testing.assert_array_equal(mine, theirs)


class Raising:
    """An array-like whose __array__ raises `error`."""

    def __init__(self, error):
        self.error = error

    def __array__(self, dtype=None):
        raise self.error


def test_an_array_like_that_fails_to_convert_is_an_error_naming_the_argument():
    nl = tricell.NeighborList(1.8)
    with pytest.raises(TypeError, match=r"^box cannot be converted to a numpy array \(got "
                                        r"Raising: no array today\)$"):
        nl.compute(P, Raising(RuntimeError("no array today")))
    with pytest.raises(ValueError, match=r"^points must be a rectangular array of numbers"):
        nl.compute(Raising(ValueError("bad")), B)
    # A failed allocation (or an interrupt) is no fault of the argument: it is not translated.
    with pytest.raises(MemoryError, match="^out of memory$"):
        nl.compute(Raising(MemoryError("out of memory")), B)


if __name__ == "__main__":
    totals = collections.Counter()
    for case in CASES:
        tally, failures = check_family(case)
        totals.update(tally)
        print(f"{case[0]:30} {case[1]:26} {dict(tally)} failures: {len(failures)}")
        for failure in failures[:5]:
            print("   ", failure)
    print(f"{sum(totals.values())} cases: {dict(totals)}")
