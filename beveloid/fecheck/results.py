"""Reading CalculiX's results: the ASCII ``.frd`` (nodal blocks: DISP, STRESS, CONTACT) and the
``.dat`` (the printed contact forces, the rotation node, the reaction), and a VTU of the fields.

The .frd's node blocks are fixed-width (Fortran ``a3, i10, 6e12.5``; CalculiX's manual, "Result
format"): a record ``-1`` starts a node's values, ``-2`` continues them, ``-3`` ends the block;
``-4`` names the block and ``-5`` its components.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

__all__ = ["ContactForce", "DatResults", "FrdBlock", "read_dat", "read_frd", "write_vtu"]


@dataclass(frozen=True)
class FrdBlock:
    """One nodal result block: node ids (n,), values (n, components), component names."""

    name: str
    node_ids: np.ndarray
    values: np.ndarray
    components: tuple

    def component(self, name: str) -> np.ndarray:
        return self.values[:, self.components.index(name)]

    def on(self, count: int, fill: float = 0.0) -> np.ndarray:
        """The values on nodes 1..count (rows by node id - 1), ``fill`` where the block has none."""
        out = np.full((count, self.values.shape[1]), fill)
        keep = self.node_ids <= count
        out[self.node_ids[keep] - 1] = self.values[keep]
        return out


def _floats(text: str, width: int = 12) -> list:
    return [float(text[i:i + width]) for i in range(0, len(text.rstrip()), width) if text[i:i + width].strip()]


def read_frd(path) -> dict:
    """{block name: :class:`FrdBlock`} of the last increment of each nodal block in an ASCII .frd."""
    blocks = {}
    name, comps, ids, rows = None, [], [], []
    with open(path) as fh:
        for line in fh:
            key = line[:3]
            if line.startswith("  100C"):
                name, comps, ids, rows = None, [], [], []
            elif key == " -4":
                name = line[3:].split()[0]
            elif key == " -5" and name is not None:
                parts = line[3:].split()
                if len(parts) < 6 or not parts[-1].endswith("ALL"):
                    comps.append(parts[0])
            elif key == " -1" and name is not None:
                ids.append(int(line[3:13]))
                rows.append(_floats(line[13:].rstrip("\n")))
            elif key == " -2" and name is not None and rows:
                rows[-1] += _floats(line[13:].rstrip("\n"))
            elif key == " -3" and name is not None:
                n = len(comps)
                values = np.array([r[:n] for r in rows], dtype=float).reshape(-1, n)
                blocks[name] = FrdBlock(name, np.asarray(ids, dtype=np.int64), values, tuple(comps))
                name = None
    return blocks


@dataclass(frozen=True)
class ContactForce:
    """The printed total of one contact pair (CF): force (N) and moment about the origin (N mm) of the
    contact forces on the slave surface, and the contact area (mm^2) when CalculiX prints it."""

    slave: str
    force_n: np.ndarray
    moment_nmm: np.ndarray
    area_mm2: float | None


@dataclass(frozen=True)
class DatResults:
    contact: tuple  # ContactForce per printed pair, in the order printed
    displacements: dict  # {node id: (3,)} of the printed node sets
    total_force_n: np.ndarray | None  # the printed total (RF, TOTALS=ONLY)


_NUM = r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?"
_HEADER = re.compile(r"[a-df-zA-DF-Z]")  #: a line with letters other than an exponent's e is a heading


def read_dat(path) -> DatResults:
    """The .dat's last increment: contact totals, printed displacements and the total reaction."""
    lines = open(path).read().splitlines()
    contact, disp, total, section, current = {}, {}, None, None, None
    for line in lines:
        low = line.strip().lower()
        nums = [float(v) for v in re.findall(_NUM, line)] if line.strip() else []
        if low.startswith("statistics for slave set"):
            current = line.split("slave set")[1].split(",")[0].strip()
            contact[current] = {"fm": None, "area": None}
            section = "cf"
        elif low.startswith("total surface force"):
            section = "cf_force"
        elif low.startswith("center of gravity") or low.startswith("moment about the center"):
            section = "cf_other"
        elif low.startswith("area"):
            section = "cf_area"
        elif low.startswith("displacements"):
            section = "disp"
        elif low.startswith("total force"):
            section = "total"
        elif _HEADER.search(line):
            section = None  # another print block (energies, ...)
        elif nums:
            if section == "cf_force" and len(nums) >= 6 and current is not None:
                contact[current]["fm"] = nums[-6:]
                section = "cf_other"
            elif section == "cf_area" and current is not None:
                contact[current]["area"] = nums[0]
                section = None
            elif section == "disp" and len(nums) >= 4:
                disp[int(nums[0])] = np.array(nums[1:4])
            elif section == "total" and len(nums) >= 3:
                total = np.array(nums[-3:])
                section = None
    out = tuple(ContactForce(k, np.array(v["fm"][:3]), np.array(v["fm"][3:]), v["area"])
                for k, v in contact.items() if v["fm"] is not None)
    return DatResults(out, disp, total)


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress of (n, 6) stresses (xx, yy, zz, xy, yz, zx) (MPa)."""
    s = stress
    return np.sqrt(0.5 * ((s[:, 0] - s[:, 1]) ** 2 + (s[:, 1] - s[:, 2]) ** 2 + (s[:, 2] - s[:, 0]) ** 2)
                   + 3.0 * (s[:, 3] ** 2 + s[:, 4] ** 2 + s[:, 5] ** 2))


def max_principal(stress: np.ndarray) -> np.ndarray:
    """The largest principal stress of (n, 6) stresses (xx, yy, zz, xy, yz, zx) (MPa)."""
    s = stress
    t = np.stack([np.stack([s[:, 0], s[:, 3], s[:, 5]], -1), np.stack([s[:, 3], s[:, 1], s[:, 4]], -1),
                  np.stack([s[:, 5], s[:, 4], s[:, 2]], -1)], -2)
    return np.linalg.eigvalsh(t)[:, -1]


def write_vtu(path, nodes_mm: np.ndarray, tets: np.ndarray, frd: dict) -> None:
    """A VTU (ParaView) of the mesh (C3D10 order = VTK's quadratic tetra) with the point fields
    displacement_mm, stress_mpa (xx, yy, zz, xy, yz, zx), von_mises_mpa, max_principal_mpa and
    contact_pressure_mpa (0 off the slave surfaces)."""
    import meshio

    n = len(nodes_mm)
    data = {}
    if "DISP" in frd:
        data["displacement_mm"] = frd["DISP"].on(n)[:, :3]
    if "STRESS" in frd:
        s = frd["STRESS"].on(n)[:, :6]
        data.update(stress_mpa=s, von_mises_mpa=von_mises(s), max_principal_mpa=max_principal(s))
    pressure = contact_pressure(frd)
    if pressure is not None:
        data["contact_pressure_mpa"] = pressure.on(n)[:, 0]
    meshio.write(str(path), meshio.Mesh(np.asarray(nodes_mm), [("tetra10", np.asarray(tets))], point_data=data),
                 file_format="vtu")


def contact_pressure(frd: dict) -> FrdBlock | None:
    """The contact pressure (MPa, >= 0) on the slave nodes, from the CONTACT block's CPRESS."""
    for block in frd.values():
        if "CPRESS" in block.components:
            p = np.maximum(block.component("CPRESS"), 0.0)[:, None]
            return FrdBlock("CPRESS", block.node_ids, p, ("CPRESS",))
    return None
