#!/usr/bin/env python3
"""Markdown tables of a pbf_frames CSV: per (substeps, iterations), the dam's and the tank's
verdict and ms per frame, LDC off and on; then the cheapest setting that is ok in both scenes.

    python3 tools/frames/frames_table.py docs/perf/h100_frames_fine_262k.csv
"""
import csv
import sys


def short(verdict):
    if verdict == "ok":
        return "ok"
    if verdict.startswith("unstable"):
        return "unstable" + (" (E)" if "energy" in verdict else " (ρ)" if "errmax" in verdict else "")
    return verdict


def main(path):
    rows = list(csv.DictReader(open(path)))
    if not rows:
        return
    cells = {}
    for r in rows:
        cells[(r["scale"], r["particles"], r["substeps"], r["iterations"], r["ldc"], r["scene"])] = r
    for scale, particles in sorted({(r["scale"], r["particles"]) for r in rows}):
        print(f"\n**{scale} scale, {particles} particles** ({rows[0]['device']}); cell: verdict, GPU ms per 1/60 s frame"
              " (auto: mean substeps); (E) energy gain, (ρ) density error > 3\n")
        print("| S | it | LDC off: dam | tank | LDC on: dam | tank |")
        print("|---|---|---|---|---|---|")
        keys = sorted({(r["substeps"], r["iterations"]) for r in rows if r["scale"] == scale and r["particles"] == particles},
                      key=lambda k: (k[0] == "auto", int(k[0]) if k[0] != "auto" else 0, int(k[1])))
        best = None
        for s, it in keys:
            out = [s, it]
            for ldc in ("0", "1"):
                both = []
                for scene in ("dam", "tank"):
                    r = cells.get((scale, particles, s, it, ldc, scene))
                    if r is None:
                        out.append("-")
                        continue
                    extra = f", S̄ {float(r['substeps_mean']):.1f}" if s == "auto" else ""
                    out.append(f"{short(r['verdict'])}, {float(r['ms_per_frame']):.2f} ms{extra}")
                    both.append(r)
                if len(both) == 2 and all(b["verdict"] == "ok" for b in both):
                    ms = max(float(b["ms_per_frame"]) for b in both)
                    if best is None or ms < best[0]:
                        best = (ms, f"S={s}, {it} iterations, LDC {'on' if ldc == '1' else 'off'}")
            print("| " + " | ".join(out) + " |")
        print(f"\nCheapest setting ok in both scenes: {best[1]}, {best[0]:.2f} ms per frame (the dearer scene)"
              if best else "\nNo setting is ok in both scenes.")


if __name__ == "__main__":
    for p in sys.argv[1:]:
        main(p)
