#!/usr/bin/python3
"""The five published trends of the DEM campaign [Trivino2025] from the two legs of bench/scenes/dem-trends-*.toml
(sweep.csv of `aggkit sweep`): markdown tables of C/N_tot, T_agg/t_ff, K/|P| and both F, means ± standard
errors over the runs of each cell, under each numerics (explicit dashpot at t_c/N; auto at t_c/50) and each
definition (at T_agg, at k t_ff).

  /usr/bin/python3 bench/dem_trends_table.py PAPER_DIR CONVERGED_DIR

Each DIR is an `aggkit sweep --out` folder of bench/scenes/dem-trends-paper.toml and -converged.toml; the
finished runs are read from DIR/points/*.json (validation/sweep/sweep_record.hpp), so that a sweep stopped
before its end is tabulated as far as it ran, or from DIR/sweep.csv (bench/results/log/dem-trends/paper, converged).

A cell "m ± s (n)" is the mean over the n runs with a finite value and its standard error (sample sd/√n); a
run that never aggregated has no T_agg and no value at T_agg; "F0" columns count such runs as F = 0 (the
paper's map)."""
import csv
import glob
import json
import math
import os
import sys


def read(folder, keys):
    """The finished runs of a sweep folder as rows {engine.<key>: value, realization, column: value}; from
    DIR/sweep.csv when the folder has no points/ (the copies kept in bench/results/log/dem-trends/)."""
    if not os.path.isdir(os.path.join(folder, "points")):
        with open(os.path.join(folder, "sweep.csv"), newline="") as f:
            return list(csv.DictReader(f))
    rows = []
    for path in sorted(glob.glob(os.path.join(folder, "points", "point*_r*.json"))):
        with open(path) as f:
            record = json.load(f)
        row = {"engine." + k: str(v) for k, v in zip(keys, record["values"])}
        row["realization"] = str(record["realization"])
        for name, value in record["columns"]:
            row[name] = "nan" if value is None else repr(value)
        rows.append(row)
    return rows


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def cell(values):
    finite = [v for v in values if not math.isnan(v)]
    if not finite:
        return "— (0)"
    m = sum(finite) / len(finite)
    s = math.sqrt(sum((v - m) ** 2 for v in finite) / (len(finite) - 1) / len(finite)) if len(finite) > 1 else 0.0
    return "%.3g ± %.2g (%d)" % (m, s, len(finite))


def select(rows, **keys):
    out = rows
    for k, v in keys.items():
        out = [r for r in out if number(r["engine." + k]) == v]
    return out


def legs(paper, converged):
    """(label, rows) for every numerics: explicit at t_c/N, then the converged leg."""
    out = []
    for n in sorted({number(r["engine.steps_per_contact"]) for r in paper}):
        out.append(("explicit t_c/%d" % n, select(paper, steps_per_contact=n)))
    out.append(("auto t_c/50", converged))
    return out


def table(title, header, rows):
    print("\n**%s**\n" % title)
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| " + " | ".join(r) + " |")


def main():
    paper = read(sys.argv[1], ["damping", "steps_per_contact", "stiffness_normalized"])
    converged = read(sys.argv[2], ["damping", "stiffness_normalized"])
    both = legs(paper, converged)
    gammas = sorted({number(r["engine.damping"]) for r in converged + paper})
    stiffness = sorted({number(r["engine.stiffness_normalized"]) for r in converged + paper})

    def over(key, values, column, fixed, f0=False):
        out = []
        for label, rows in both:
            line = [label]
            for v in values:
                sel = select(rows, **{key: v}, **fixed)
                vals = [number(r[column]) for r in sel]
                if f0:
                    vals = [0.0 if math.isnan(number(r["aggregation_time"])) else x for r, x in zip(sel, vals)]
                line.append(cell(vals))
            out.append(line)
        return out

    g_head = ["numerics"] + ["γ_n = %g" % g for g in gammas]
    k_head = ["numerics"] + ["k̃_n = %g" % k for k in stiffness]
    for column, what in [("aggregation_time_ff", "T_agg/t_ff"), ("components_fraction_at_agg", "C/N_tot at T_agg"),
                         ("components_fraction_at_1tff", "C/N_tot at 1 t_ff"), ("components_fraction_at_2tff", "C/N_tot at 2 t_ff"),
                         ("virial_ratio_at_2tff", "K/|P| at 2 t_ff")]:
        table("%s against γ_n at k̃_n = 10^6" % what, g_head, over("damping", gammas, column, {"stiffness_normalized": 1e6}))
        table("%s against γ_n, pooled over k̃_n" % what, g_head, over("damping", gammas, column, {}))
    for column, what in [("aggregation_time_ff", "T_agg/t_ff"), ("components_fraction_at_agg", "C/N_tot at T_agg"),
                         ("components_fraction_at_1tff", "C/N_tot at 1 t_ff"), ("components_fraction_at_1.5tff", "C/N_tot at 1.5 t_ff"),
                         ("components_fraction_at_2tff", "C/N_tot at 2 t_ff"), ("virial_ratio_at_2tff", "K/|P| at 2 t_ff")]:
        table("%s against k̃_n at γ_n = 500" % what, k_head, over("stiffness_normalized", stiffness, column, {"damping": 500.0}))
    for column, what, f0 in [("fractal_dimension_com_at_agg", "F (2R … r_90) at T_agg", False),
                             ("fractal_dimension_com_all_at_agg", "F (every sphere) at T_agg", False),
                             ("fractal_dimension_com_all_at_agg", "F (every sphere) at T_agg, F0 where T_agg is undefined", True),
                             ("fractal_dimension_com_at_2tff", "F (2R … r_90) at 2 t_ff", False),
                             ("fractal_dimension_com_all_at_2tff", "F (every sphere) at 2 t_ff", False),
                             ("fractal_dimension_com_all_at_2tff", "F (every sphere) at 2 t_ff, F0 where T_agg is undefined", True)]:
        for label, rows in both:
            lines = []
            for g in gammas:
                line = ["γ_n = %g" % g]
                for k in stiffness:
                    sel = select(rows, damping=g, stiffness_normalized=k)
                    vals = [number(r[column]) for r in sel]
                    if f0:
                        vals = [0.0 if math.isnan(number(r["aggregation_time"])) else x for r, x in zip(sel, vals)]
                    line.append(cell(vals))
                lines.append(line)
            table("%s, %s (rows γ_n, columns k̃_n)" % (what, label), ["γ_n"] + k_head[1:], lines)


if __name__ == "__main__":
    main()
