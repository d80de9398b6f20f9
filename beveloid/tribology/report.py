"""The tribology in the commands' words: the efficiency map's JSON, the cells' CSV, the text lines."""
from __future__ import annotations

import csv
import math
import os

from .result import TribologyResult, _num

#: the keys of each map entry's efficiency-map block, (name, attribute)
MAP_KEYS = ("input_power_w", "mesh_power_loss_w", "efficiency", "friction_coefficient_global",
            "friction_coefficient_mean", "lambda_min", "flash_temperature_max_c", "contact_temperature_max_c",
            "scuffing_safety")


def map_json(grid) -> dict:
    """The "efficiency_map" block: per key a [torque][speed] table (null where not computed)."""
    out = {"torque_nm": [row[0].torque_nm for row in grid], "speed_rpm": [t.speed_rpm for t in grid[0]]}
    for key in MAP_KEYS:
        out[key] = [[_num(getattr(t, key)) for t in row] for row in grid]
    return out


def write_csv(grid, folder) -> str:
    """DIR/tribology.csv: one row per loaded cell and position, for every torque and speed."""
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "tribology.csv")
    tmp = path + ".tmp"
    cell = lambda v: "" if v is None or not math.isfinite(v) else repr(float(v))  # noqa: E731
    with open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(("torque_nm", "speed_rpm") + TribologyResult.CSV_COLUMNS)
        for row in grid:
            for t in row:
                for r in t.csv_rows():
                    w.writerow([repr(t.torque_nm), repr(t.speed_rpm), *r[:3], *(cell(v) for v in r[3:])])
    os.replace(tmp, path)
    return path


def format_lines(t: TribologyResult) -> list:
    """A few lines of text: power, loss, efficiency, friction, film, temperatures, scuffing."""
    f = lambda v, spec: "-" if v is None or not math.isfinite(v) else format(v, spec)  # noqa: E731
    lines = [f"tribology at {t.speed_rpm:g} rpm ({'fixed friction coefficient' if t.fixed_friction else 'ISO/TR 14179-2 local friction'}):"
             f" input {f(t.input_power_w, '.1f')} W, mesh loss {f(t.mesh_power_loss_w, '.2f')} W (mean over the cycle),"
             f" efficiency {f(t.efficiency * 100 if t.efficiency is not None else None, '.3f')} %, H_V {f(t.loss_factor_hv, '.4f')}",
             f"  friction coefficient: global (ISO/TR 14179-2) {f(t.friction_coefficient_global, '.4f')}, load-weighted mean "
             f"{f(t.friction_coefficient_mean, '.4f')}; smallest film parameter lambda {f(t.lambda_min, '.2f')}",
             f"  flash temperature max {f(t.flash_temperature_max_c, '.1f')} K, bulk {f(t.bulk_temperature_c, '.1f')} C, "
             f"contact max {f(t.contact_temperature_max_c, '.1f')} C; scuffing temperature "
             f"{f(t.scuffing_temperature_c, '.1f')} C, safety S_B {f(t.scuffing_safety, '.2f')}"]
    if t.scuffing_safety is None:
        lines.append("  no scuffing safety: give [lubricant] fzg_load_stage (the oil's FZG scuffing load stage)")
    return lines
