#!/usr/bin/python3
"""Writes the epoch file (epoch_file.py): three epochs of structures as machine-learning
potentials see them in training, built only from what Debian's python3-ase ships.

- crystals: 1 536 periodic cells with the size profile of a stratified sample of Matbench's
  mp_e_form (1 536 structures of 1 to 444 atoms, median 24, mean 49: 75 238 atoms; here sizes
  drawn lognormal, each cell the repeat closest to its size), each an ASE crystal (the
  elemental crystals of the dcdft collection, and binary and ternary crystals of
  ase.build.bulk and ase.spacegroup.crystal) repeated along its narrowest axes, then strained
  by a random deformation (up to a few percent, shears included) and rattled by 0.02 A, so
  that every cell is triclinic and no two are alike;
- molecules: 4 096 molecules of the g2 and s22 collections (7 atoms on average), each rotated
  at random and moved anywhere in a 100 A cube; open, with an all-zero cell, as data sets of
  molecules give them;
- clusters: 4 096 clusters of g2 and s22 molecules with the size profile of a sample of QMugs
  (drug-like molecules of 13 to 209 atoms, median 52, mean 55), packed at random in a sphere
  of organic density (0.08 atoms/A^3, no two atoms of different molecules closer than 2 A);
  open, all-zero cell.

The cutoff is 5 A for every epoch (the common radius of MACE, NequIP and SchNet models).
Everything is drawn from fixed seeds: the same ASE gives the same file.

  make_epochs.py OUTPUT [--scale F]     (F < 1: fewer structures, for a quick run)
"""
import argparse
import os
import sys

import numpy as np
from ase.build import bulk
from ase.collections import dcdft, g2, s22
from ase.spacegroup import crystal

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epoch_file import Epoch, write  # noqa: E402

CUTOFF = 5.0


def crystal_prototypes():
    """Periodic unit cells: dcdft's elemental crystals and a few dozen compounds."""
    cells = [atoms.copy() for atoms in dcdft]
    for formula, structure, a in [
            ("NaCl", "rocksalt", 5.64), ("MgO", "rocksalt", 4.21), ("LiF", "rocksalt", 4.03),
            ("KCl", "rocksalt", 6.29), ("GaAs", "zincblende", 5.65), ("ZnS", "zincblende", 5.41),
            ("SiC", "zincblende", 4.36), ("CsCl", "cesiumchloride", 4.12),
            ("CaF2", "fluorite", 5.46), ("UO2", "fluorite", 5.47)]:
        cells.append(bulk(formula, structure, a=a))
        if structure != "fluorite":  # ASE builds no cubic fluorite cell
            cells.append(bulk(formula, structure, a=a, cubic=True))
    for formula, a, c in [("ZnO", 3.25, 5.21), ("GaN", 3.19, 5.19), ("AlN", 3.11, 4.98)]:
        cells.append(bulk(formula, "wurtzite", a=a, c=c))
    cells.append(crystal(["Sr", "Ti", "O"], [(0, 0, 0), (0.5, 0.5, 0.5), (0.5, 0.5, 0)],
                         spacegroup=221, cellpar=[3.905, 3.905, 3.905, 90, 90, 90]))
    cells.append(crystal(["Ti", "O"], [(0, 0, 0), (0.305, 0.305, 0)], spacegroup=136,
                         cellpar=[4.59, 4.59, 2.96, 90, 90, 90]))
    cells.append(crystal(["Si", "O"], [(0.4697, 0, 0), (0.4135, 0.2669, 0.1191)],
                         spacegroup=152, cellpar=[4.916, 4.916, 5.405, 90, 90, 120]))
    cells.append(crystal(["Al", "O"], [(0, 0, 0.3523), (0.3064, 0, 0.25)], spacegroup=167,
                         cellpar=[4.76, 4.76, 12.99, 90, 90, 120]))
    cells.append(crystal(["Mg", "Al", "O"], [(0.125, 0.125, 0.125), (0.5, 0.5, 0.5),
                                             (0.263, 0.263, 0.263)],
                         spacegroup=227, setting=2, cellpar=[8.08, 8.08, 8.08, 90, 90, 90]))
    return cells


def widths(cell):
    """Perpendicular widths of a cell whose rows are the lattice vectors."""
    return 1.0 / np.linalg.norm(np.linalg.inv(cell), axis=0)


LARGEST = 444  # atoms: the largest structure of the Matbench sample


def repeated(prototype, target):
    """The prototype repeated along its narrowest axes to the atom count closest to `target`,
    at most LARGEST (never fewer than its own atoms)."""
    repeats = np.ones(3, dtype=int)
    w = widths(prototype.cell[:])
    while True:
        grown = repeats.copy()
        grown[np.argmin(w * repeats)] += 1
        atoms, more = len(prototype) * repeats.prod(), len(prototype) * grown.prod()
        if more > LARGEST or abs(more - target) >= abs(atoms - target):
            return prototype.repeat(tuple(repeats))
        repeats = grown


def crystals(rng, count):
    prototypes = crystal_prototypes()
    cells, positions = [], []
    sizes = np.clip(np.rint(rng.lognormal(np.log(26.0), 1.19, count)), 1, LARGEST)
    for target in sizes:
        atoms = repeated(prototypes[rng.integers(len(prototypes))], target)
        # A random deformation: normal strains of about 2 %, shears of about 3 %.
        deformation = np.eye(3) + np.diag(rng.normal(0, 0.02, 3)) + \
            (1 - np.eye(3)) * rng.normal(0, 0.03, (3, 3))
        cell = atoms.cell[:] @ deformation.T
        x = atoms.positions @ deformation.T + rng.normal(0, 0.02, (len(atoms), 3))
        cells.append(cell)
        positions.append(x)
    return cells, positions


def rotation(rng):
    """A uniformly random rotation matrix (QR of a Gaussian matrix, signs fixed)."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def molecule_templates():
    return [atoms.positions - atoms.positions.mean(axis=0) for atoms in list(g2) + list(s22)]


def molecules(rng, count):
    templates = molecule_templates()
    positions = []
    for _ in range(count):
        x = templates[rng.integers(len(templates))] @ rotation(rng).T
        positions.append(x + rng.uniform(-50, 50, 3))
    return positions


def clusters(rng, count):
    templates = molecule_templates()
    density, gap = 0.08, 2.0
    positions = []
    sizes = np.clip(np.rint(rng.lognormal(np.log(50.0), 0.42, count)), 13, 209)
    for target in sizes:
        radius = (3 * target / (4 * np.pi * density)) ** (1 / 3)
        placed = np.empty((0, 3))
        failures = 0
        while len(placed) < target:
            x = templates[rng.integers(len(templates))] @ rotation(rng).T
            direction = rng.normal(size=3)
            x = x + direction / np.linalg.norm(direction) * radius * rng.uniform() ** (1 / 3)
            if len(placed) and np.min(np.linalg.norm(
                    placed[:, None, :] - x[None, :, :], axis=2)) < gap:
                failures += 1
                if failures % 50 == 0:
                    radius *= 1.05  # crowded: let the sphere grow
                continue
            placed = np.vstack([placed, x])
        positions.append(placed + rng.uniform(-50, 50, 3))
    return positions


def batch(name, cells, positions, pbc):
    ptr = np.concatenate([[0], np.cumsum([len(x) for x in positions])]).astype(np.int64)
    return Epoch(name, CUTOFF, ptr, np.array(cells, dtype=np.float64).reshape(-1, 3, 3),
                 np.broadcast_to(np.array(pbc, dtype=bool), (len(positions), 3)),
                 np.concatenate(positions).astype(np.float64))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("output")
    parser.add_argument("--scale", type=float, default=1.0)
    args = parser.parse_args()
    count = lambda n: max(1, int(round(n * args.scale)))  # noqa: E731
    cells, x = crystals(np.random.default_rng(1), count(1536))
    epochs = [batch("crystals", cells, x, True)]
    x = molecules(np.random.default_rng(2), count(4096))
    epochs.append(batch("molecules", np.zeros((len(x), 3, 3)), x, False))
    x = clusters(np.random.default_rng(3), count(4096))
    epochs.append(batch("clusters", np.zeros((len(x), 3, 3)), x, False))
    write(args.output, epochs)
    for e in epochs:
        sizes = np.diff(e.ptr)
        print("%-9s %5d structures, %6d atoms (median %d, largest %d), cutoff %g"
              % (e.name, len(sizes), sizes.sum(), np.median(sizes), sizes.max(), e.cutoff))


if __name__ == "__main__":
    main()
