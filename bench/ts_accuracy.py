#!/usr/bin/python3
"""TS against ED in distribution [Degond2024, Sec. 4.2]: for each (N, V_f, dt_factor) both engines run the
published setup (discs of radius 0.2, reflecting walls, square-lattice start, unit speed in uniform
directions) to one cluster over R realizations through `aggkit run`, and the final aggregates are compared:
box-counting D_f (relative difference), N_c of eq. 4.6 with i = j (contacts_with_self, relative difference)
and P(r) at 90 radii on (2R, 20R] (largest |ΔP| in combined standard errors, and the share within one).

  bench/ts_accuracy.py [--counts 100,400,900,2500] [--fractions 0.1,0.2,0.3] [--dt-factors 0.005]
                       [--contact-time on|off] [--realizations 10] [--build build] [--out results/ts-accuracy]

Prints one line per case and the mean |ΔD_f|; appends the figures to build/bench/figures/ts_accuracy.csv
($AGGKIT_BENCH_FIGURES) for bench/check. Standard library only (run by /usr/bin/python3)."""
import argparse, csv, datetime, json, math, os, subprocess, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SCENE = """name = "ts-accuracy"
[particles]
dimension = 2
count = {n}
radius = 0.2
volume_fraction = {nu}
boundary = "reflecting"
initial = {{ lattice = "square", speed = 1.0, directions = "uniform" }}
seed = 1
realizations = {reps}
[time]
end = 1.0
outputs = [1.0]
[[engine]]
name = "ed"
stop = "one_cluster"
[[engine]]
name = "ts"
dt_factor = {dtf}
contact_time = {ct}
stop = "one_cluster"
[observe]
series = ["clusters"]
final = ["contacts_with_self", "fractal_dimension_box", "pair_distribution"]
"""


def profile(path):
    with open(path) as f:
        return [(float(r["P"]), float(r["P_stderr"])) for r in csv.DictReader(f)]


def main():
    a = argparse.ArgumentParser()
    a.add_argument("--counts", default="100,400,900,2500")
    a.add_argument("--fractions", default="0.1,0.2,0.3")
    a.add_argument("--dt-factors", default="0.005")
    a.add_argument("--contact-time", default="on", choices=["on", "off"])
    a.add_argument("--realizations", type=int, default=10)
    a.add_argument("--build", default=os.path.join(ROOT, "build"))
    a.add_argument("--out", default=os.path.join(ROOT, "results", "ts-accuracy"))
    args = a.parse_args()
    command = "bench/ts_accuracy.py " + " ".join(sys.argv[1:])
    figures = os.environ.get("AGGKIT_BENCH_FIGURES") or os.path.join(args.build, "bench", "figures")
    os.makedirs(figures, exist_ok=True)
    os.makedirs(args.out, exist_ok=True)
    with open("/proc/loadavg") as f:
        print("# load average:", f.read().strip())
    rows, dfs = [], []
    for n in [int(x) for x in args.counts.split(",")]:
        for nu in args.fractions.split(","):
            for dtf in args.dt_factors.split(","):
                tag = f"N{n}-nu{nu}-dt{dtf}-ct{args.contact_time}"
                scene = os.path.join(args.out, tag + ".toml")
                out = os.path.join(args.out, tag)
                with open(scene, "w") as f:
                    f.write(SCENE.format(n=n, nu=nu, reps=args.realizations, dtf=dtf,
                                         ct="true" if args.contact_time == "on" else "false"))
                subprocess.run([os.path.join(args.build, "aggkit"), "run", scene, "-o", out], capture_output=True)
                e = json.load(open(os.path.join(out, "ed", "final.json")))
                t = json.load(open(os.path.join(out, "ts", "final.json")))
                df = (t["fractal_dimension_box"] - e["fractal_dimension_box"]) / e["fractal_dimension_box"]
                nc = (t["contacts_with_self"] - e["contacts_with_self"]) / e["contacts_with_self"]
                z = [abs(p - q) / max(math.hypot(sp, sq), 1e-300)
                     for (p, sp), (q, sq) in zip(profile(os.path.join(out, "ts", "pair_distribution.csv")),
                                                 profile(os.path.join(out, "ed", "pair_distribution.csv")))]
                within = sum(1 for x in z if x <= 1) / len(z)
                dfs.append(abs(df))
                print(f"N {n:6d} V_f {nu} dt_factor {dtf} contact_time {args.contact_time}: D_f TS "
                      f"{t['fractal_dimension_box']:.4f} ± {t['fractal_dimension_box_stderr']:.4f} ED "
                      f"{e['fractal_dimension_box']:.4f} ± {e['fractal_dimension_box_stderr']:.4f} ({100 * df:+.2f} %), "
                      f"N_c TS {t['contacts_with_self']:.4f} ED {e['contacts_with_self']:.4f} ({100 * nc:+.2f} %), "
                      f"P(r) max {max(z):.2f} se, {100 * within:.0f} % within 1 se; wall TS {t['wall_seconds']:.3f} s "
                      f"ED {e['wall_seconds']:.3f} s per realization", flush=True)
                case = f"N={n} nu={nu} dt_factor={dtf} contact_time={args.contact_time}"
                rows += [(case, "df_relative_difference", abs(df)), (case, "nc_relative_difference", abs(nc)),
                         (case, "pr_max_standard_errors", max(z))]
    if dfs:
        print(f"mean |ΔD_f| {100 * sum(dfs) / len(dfs):.2f} %, largest {100 * max(dfs):.2f} %")
        rows.append((f"counts={args.counts} fractions={args.fractions} dt_factors={args.dt_factors} "
                     f"contact_time={args.contact_time}", "df_mean_relative_difference", sum(dfs) / len(dfs)))
    path = os.path.join(figures, "ts_accuracy.csv")
    fresh = not os.path.exists(path)
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    with open(path, "a", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        if fresh:
            w.writerow(["date", "bench", "case", "figure", "value", "unit", "command"])
        for case, figure, value in rows:
            w.writerow([date, "ts_accuracy", case, figure, f"{value:.6g}", "1", command])


if __name__ == "__main__":
    main()
