"""One table of benches/gpu/item4.sh's profiles: per method, lattice, kernel and plan, a step's
time per cell-channel and against the device bound, the 8 steps of a frame (the sum of the
GPU times of the propagation passes and, for ILPV, their clamp compensation) next to seed 000's
Table 4.2, and the frame.

The 8 steps are the passes' own times, so for the async plan they are the work, not the span
its queues overlap: the frame's median is what shows the overlap (async against sequential).
Usage: python3 item4_table.py PROFILE.json...  (file names METHOD-KERNEL-PLAN-PARTS-LATTICE.json,
or METHOD-KERNEL-PLAN-PARTS.json for a profile of several lattices)."""

import json
import os
import sys

# Seed 000's Table 4.2: CUDA on a GTX 470, ms for 8 steps at 32³, 64³ and 128³.
THESIS_MS = {"32": 2.7, "64": 18.2, "128": 140.9}


def rows(path):
    """The table's rows for one profile."""
    name = os.path.basename(path)[: -len(".json")]
    head, _, last = name.rpartition("-")
    variant = head if last.isdigit() else name
    with open(path) as f:
        profile = json.load(f)
    for config in profile["configs"]:
        core = config.get("core")
        if core is None:
            continue
        lattice = config["value"]
        steps_ns = sum(
            p["median_ns"]
            for p in profile["passes"]
            if p["method"] == config["method"]
            and p["value"] == lattice
            and p["pass"].startswith(("propagate", "compensate"))
        )
        yield {
            "device": profile["device"],
            "variant": variant,
            "lattice": lattice,
            "ns_per_unit": core["ns_per_unit"],
            "fraction": core["fraction_of_bound"],
            "steps_ms": steps_ns / 1e6,
            "frame_ms": config["frame_median_ns"] / 1e6,
        }


def main(paths):
    if not paths:
        sys.exit("usage: item4_table.py PROFILE.json...")
    table = sorted(
        (row for path in paths for row in rows(path)),
        key=lambda row: (row["variant"], int(row["lattice"])),
    )
    devices = sorted({row["device"] for row in table})
    print(f"device: {', '.join(devices)}\n")
    print(
        "| variant | lattice | ns per cell-channel | % of bound | 8 steps, ms "
        "| Table 4.2, ms | frame, ms |"
    )
    print("|---|---|---|---|---|---|---|")
    for row in table:
        thesis = THESIS_MS.get(row["lattice"])
        print(
            f"| {row['variant']} | {row['lattice']} | {row['ns_per_unit']:.3f} "
            f"| {100 * row['fraction']:.1f}% | {row['steps_ms']:.3f} "
            f"| {'-' if thesis is None else thesis} | {row['frame_ms']:.3f} |"
        )


if __name__ == "__main__":
    main(sys.argv[1:])
