#!/usr/bin/env python3
"""Work-precision of aggkit against the peer a user would write with scipy, both cases in one run:

  ballistic  K = (i^1/3 + j^1/3)^2 sqrt(1/i + 1/j), λ = 0.01, N = 2000, cutoff — peer bench/peers/scipy_direct.py
             (numpy direct O(N^2) sums);
  constant   K = 1, λ = 0.1, N = 32768, drop — peer bench/peers/scipy_constant.py (scipy.signal.fftconvolve; the
             direct sum np.convolve is timed per call and its run time given as that cost × the peer's count of
             right-hand sides, since a run would take hours);

monodisperse start, M0, M2, M3 at t = 1, 10, 100. The error of a run is the largest relative error of those nine
numbers against aggkit at rtol 1e-12 (bdf-gmres; its agreement with the most accurate scipy run is printed).
Each scipy method (DOP853, LSODA, BDF; the implicit ones with scipy's finite-difference Jacobians) runs in a child
process stopped after --timeout seconds; aggkit runs in this process (the module's import excluded, the model's
set-up included). aggkit and scipy runs alternate, so that machine load affects both alike. scipy is Debian's
python3-scipy: installed with apt-get if missing.

  PYTHONPATH=build/python /usr/bin/python3 bench/scipy_vs_aggkit.py [--cases ballistic constant]
      [--scipy-methods DOP853 LSODA BDF] [--scipy-rtol 1e-6 1e-8] [--implicit-rtol 1e-6]
      [--aggkit-methods bdf-gmres adams erk auto] [--aggkit-rtol 1e-6 1e-8 1e-9 2e-10] [--timeout 1800]
      [--implicit-timeout 300] [--csv FILE] [--analyse-since DATE]

(--implicit-rtol: the tolerances at which scipy's LSODA and BDF run; their finite-difference Jacobians cost N
right-hand sides each, so they are run where they are cheapest.)

Prints one line per run and, per case, the ratio (scipy's fastest run at an error ≤ e) / (aggkit's fastest run at
an error ≤ e) for each scipy run's error e. Every run is appended to --csv (default
build/bench/scipy_vs_aggkit_runs.csv) for bench/work_precision_plot.py; the headline ratios go to
build/bench/figures/scipy_vs_aggkit.csv for bench/check.
"""
import argparse
import csv
import datetime
import multiprocessing
import os
import subprocess
import sys
import time


def ensure_scipy():
    try:
        import scipy  # noqa: F401
    except ImportError:
        print("installing Debian's python3-scipy", flush=True)
        sudo = [] if os.geteuid() == 0 else ["sudo"]
        subprocess.run(sudo + ["apt-get", "install", "-y", "-q", "python3-scipy"], check=True)


ensure_scipy()
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "peers"))
import scipy_constant  # noqa: E402
import scipy_direct  # noqa: E402
import aggkit  # noqa: E402

TIMES = (1.0, 10.0, 100.0)
CASES = {
    "ballistic": dict(kernel="ballistic", lam=0.01, size=2000, truncation="cutoff", peer=scipy_direct),
    "constant": dict(kernel="constant", lam=0.1, size=32768, truncation="drop", peer=scipy_constant),
}


def aggkit_run(case, method, rtol):
    c = CASES[case]
    started = time.perf_counter()
    model = aggkit.Model(c["kernel"], lam=c["lam"], size=c["size"], truncation=c["truncation"])
    solution = aggkit.integrate(model, np.array(TIMES), rtol=rtol, method=method)
    moments = np.array([solution.moment(0), solution.moment(2), solution.moment(3)]).T
    return moments, time.perf_counter() - started, solution.statistics


def _scipy_child(case, method, rtol, queue):
    c = CASES[case]
    try:
        queue.put(c["peer"].solve(c["size"], c["lam"], TIMES, rtol, 1e-14, method))
    except Exception as e:  # a failed solve (solve_ivp's message) is reported, not raised
        queue.put(str(e))


def scipy_run(case, method, rtol, timeout):
    """(moments, seconds, right-hand sides), or (None, seconds, message) for a run stopped or failed."""
    queue = multiprocessing.Queue()
    child = multiprocessing.Process(target=_scipy_child, args=(case, method, rtol, queue))
    started = time.perf_counter()
    child.start()
    try:
        result = queue.get(timeout=timeout)
    except Exception:
        child.kill()
        child.join()
        return None, time.perf_counter() - started, f"stopped after {timeout:g} s"
    child.join()
    if isinstance(result, str):
        return None, time.perf_counter() - started, "failed: " + result
    return result


def direct_convolution_seconds(size, repeats=2):
    n = np.random.default_rng(1).random(size)
    started = time.perf_counter()
    for _ in range(repeats):
        np.convolve(n, n)
    return (time.perf_counter() - started) / repeats


def error(moments, reference):
    return float(np.max(np.abs(moments / reference - 1.0)))


def schedule(args):
    """The runs of one case, aggkit and scipy alternating."""
    ours = [("aggkit", m, r) for r in args.aggkit_rtol for m in args.aggkit_methods]
    peers = [("scipy", m, r) for r in args.scipy_rtol for m in args.scipy_methods if m not in ("LSODA", "BDF")]
    peers += [("scipy", m, r) for r in args.implicit_rtol for m in args.scipy_methods if m in ("LSODA", "BDF")]
    runs = []
    while ours or peers:
        for queue in (ours, ours, peers):  # two aggkit runs (a second or two) per scipy run (a minute or more)
            if queue:
                runs.append(queue.pop(0))
    return runs


def record(args, row):
    """Appends one run to --csv at once (a long run stopped midway keeps what it measured)."""
    os.makedirs(os.path.dirname(args.csv), exist_ok=True)
    with open(args.csv, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["date", "case", "code", "method", "rtol", "seconds", "error", "note", "command"],
                           lineterminator="\n")
        if f.tell() == 0:
            w.writeheader()
        w.writerow(dict(row, date=args.stamp, command=args.command))


def run_case(case, args, rows):
    print(f"\n## {case}: {CASES[case]}", flush=True)
    reference, seconds, stats = aggkit_run(case, "bdf-gmres", 1e-12)
    print(f"reference: aggkit bdf-gmres rtol 1e-12, {seconds:.2f} s, {stats['steps']} steps", flush=True)
    for code, method, rtol in schedule(args):
        if code == "aggkit":
            moments, seconds, stats = aggkit_run(case, method, rtol)
            note = f"{stats['steps']} steps, {stats['rhs_evaluations']} f, {stats['jacobian_vector_products']} Jv"
            if method == "auto":
                note += f", bdf from t = {stats['stiff_from']:.3g}" if stats["stiff_from"] >= 0 else ", erk throughout"
        else:
            limit = args.implicit_timeout if method in ("LSODA", "BDF") else args.timeout
            moments, seconds, detail = scipy_run(case, method, rtol, limit)
            note = f"{detail} f" if moments is not None else detail
        err = error(moments, reference) if moments is not None else float("nan")
        rows.append(dict(case=case, code=code, method=method, rtol=rtol, seconds=seconds, error=err, note=note))
        record(args, rows[-1])
        print(f"{code:6} {method:10} rtol {rtol:<7g} {seconds:9.3f} s  error {err:9.2e}  ({note})", flush=True)
    scipy_ok = [r for r in rows if r["case"] == case and r["code"] == "scipy" and r["error"] == r["error"]]
    if scipy_ok:
        best = min(scipy_ok, key=lambda r: r["error"])
        print(f"reference vs the most accurate scipy run ({best['method']} rtol {best['rtol']:g}): {best['error']:.1e}")
    if case == "constant":
        per_call = direct_convolution_seconds(CASES[case]["size"])
        for r in scipy_ok:
            evaluations = int(r["note"].split()[0])
            rows.append(dict(r, method=r["method"] + " direct", seconds=per_call * evaluations,
                             note=f"np.convolve {per_call:.3f} s per call × {evaluations} f (estimated)"))
            record(args, rows[-1])
            print(f"scipy  {r['method'] + ' direct':10} rtol {r['rtol']:<7g} {rows[-1]['seconds']:9.1f} s  error "
                  f"{r['error']:9.2e}  ({rows[-1]['note']})", flush=True)


def ratios(case, rows, figures):
    """For each scipy run's error e: scipy's fastest run at error ≤ e over aggkit's fastest at error ≤ e."""
    mine = [r for r in rows if r["case"] == case and r["code"] == "aggkit"]
    theirs = [r for r in rows if r["case"] == case and r["code"] == "scipy" and r["error"] == r["error"]]
    print(f"\nratios, {case} (scipy's fastest at error ≤ e / aggkit's fastest at error ≤ e):")
    for direct in (False, True):
        pool = [r for r in theirs if r["method"].endswith(" direct") == direct]
        for run in sorted(pool, key=lambda r: r["error"]):
            e = run["error"]
            s = min((r for r in pool if r["error"] <= e), key=lambda r: r["seconds"])
            matches = [r for r in mine if r["error"] <= e]
            if not matches:
                print(f"  e = {e:.1e} ({run['method']} rtol {run['rtol']:g}): no aggkit run as accurate")
                continue
            a = min(matches, key=lambda r: r["seconds"])
            ratio = s["seconds"] / a["seconds"]
            print(f"  e = {e:.1e} ({run['method']} rtol {run['rtol']:g}): scipy's fastest {s['method']} rtol {s['rtol']:g} "
                  f"{s['seconds']:.1f} s vs aggkit {a['method']} rtol {a['rtol']:g} ({a['error']:.1e}) {a['seconds']:.3f} s: "
                  f"{ratio:.0f}x")
            # Named by the scipy run that sets the error (stable from run to run).
            figures.append((f"case={case} scipy={run['method']} rtol={run['rtol']:g}", "speedup_at_equal_error", ratio, "x"))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--scipy-methods", nargs="*", default=["DOP853", "LSODA", "BDF"])
    parser.add_argument("--scipy-rtol", type=float, nargs="+", default=[1e-6, 1e-8])
    parser.add_argument("--aggkit-methods", nargs="+", default=["bdf-gmres", "adams", "erk", "auto"])
    parser.add_argument("--implicit-rtol", type=float, nargs="+", default=[1e-6])
    parser.add_argument("--aggkit-rtol", type=float, nargs="+", default=[1e-6, 1e-8, 1e-9, 2e-10])
    parser.add_argument("--timeout", type=float, default=1800.0)
    parser.add_argument("--implicit-timeout", type=float, default=300.0)
    parser.add_argument("--analyse-since", metavar="DATE", help="run nothing: the ratios of the runs in --csv recorded "
                        "since DATE (UTC, as in its date column), e.g. of concurrent invocations, one per case")
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--csv", default=os.path.join(here, "build", "bench", "scipy_vs_aggkit_runs.csv"))
    args = parser.parse_args()
    args.stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    args.command = "PYTHONPATH=build/python /usr/bin/python3 bench/scipy_vs_aggkit.py " + " ".join(sys.argv[1:])
    rows, figures = [], []
    if args.analyse_since:  # no runs: the ratios of the runs recorded in --csv since that date (concurrent invocations)
        with open(args.csv) as f:
            for r in csv.DictReader(f):
                if r["date"] >= args.analyse_since:
                    rows.append(dict(r, rtol=float(r["rtol"]), seconds=float(r["seconds"]), error=float(r["error"])))
    for case in args.cases:
        if not args.analyse_since:
            run_case(case, args, rows)
        ratios(case, rows, figures)
    stamp, command = args.stamp, args.command
    folder = os.environ.get("AGGKIT_BENCH_FIGURES") or os.path.join(here, "build", "bench", "figures")
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "scipy_vs_aggkit.csv"), "a", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        for case, figure, value, unit in figures:
            w.writerow([stamp, "scipy_vs_aggkit", case, figure, f"{value:.4g}", unit, command])


if __name__ == "__main__":
    main()
