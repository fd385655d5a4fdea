#!/usr/bin/python3
"""CPU-time estimate of a DEM gravitational campaign (validation/scenes/dem-gravitational-campaign.toml) from a
measured cost per step and measured aggregation times.

  /usr/bin/python3 bench/dem_campaign_cost.py SECONDS_PER_STEP T_FF ZETA:TAGG_OVER_TFF ... [--end 40]
      [--gammas 10,100,...] [--stiffness 1e5,...] [--realizations 3] [--ranks 2] [--zeta-min Z]
      [--dashpot implicit|explicit] [--implicit-factor F]

Units G = m = R = 1, 650 equal spheres, m_eff = 1/2. A run's steps are min(T_agg, end)/dt with the engine's
default dt, t_c = π √(m_eff/k_n): t_c/50 with the implicit dashpot (the engine's default without friction; its
steps cost --implicit-factor times an explicit one where γ_n dt/m_eff > 0.2, where the engine switches it on),
min(t_c/50, m_eff/(5 γ_n)) with the explicit one (--dashpot explicit: the engine before the implicit dashpot). T_agg/t_ff is interpolated (log ζ) from the
measured (ζ, T_agg/t_ff) pairs, ζ = γ_n/(2 √(k_n m_eff)) the damping ratio: the measurements at k̃_n = 10^5,
10^6 and 10^7 fall on one curve of ζ (bench/results/log/dem-campaign.md). Below --zeta-min the cloud does not
aggregate and the run lasts to --end. Prints the CPU seconds of the campaign and its wall time on --ranks
ranks with a core each (perfect balance)."""
import argparse
import bisect
import math


def main():
    p = argparse.ArgumentParser()
    p.add_argument("seconds_per_step", type=float)
    p.add_argument("t_ff", type=float)
    p.add_argument("measured", nargs="+", help="zeta:T_agg/t_ff pairs")
    p.add_argument("--end", type=float, default=40.0)
    p.add_argument("--gammas", default="10,100,1000,10000,100000")
    p.add_argument("--stiffness", default="1e5,5.62341325e5,3.16227766e6,1.77827941e7,1e8")
    p.add_argument("--realizations", type=int, default=3)
    p.add_argument("--ranks", type=int, default=2)
    p.add_argument("--zeta-min", type=float, required=True)
    p.add_argument("--dashpot", choices=["implicit", "explicit"], default="implicit")
    p.add_argument("--implicit-factor", type=float, default=1.0,
                   help="cost of an implicit-dashpot step over an explicit one (measured: bench/results/log/dem-campaign.md)")
    a = p.parse_args()
    pairs = sorted((float(z), float(t)) for z, t in (m.split(":") for m in a.measured))
    zs = [math.log(z) for z, _ in pairs]

    def t_agg(zeta):
        if zeta < a.zeta_min:
            return None
        x = math.log(zeta)
        if x <= zs[0]:
            return pairs[0][1]
        if x >= zs[-1]:
            return pairs[-1][1]
        i = bisect.bisect(zs, x)
        f = (x - zs[i - 1]) / (zs[i] - zs[i - 1])
        return pairs[i - 1][1] + f * (pairs[i][1] - pairs[i - 1][1])

    total = 0.0
    m_eff = 0.5
    print("gamma_n  k_n  zeta  T_agg/t_ff  steps  cpu_s")
    for g in (float(v) for v in a.gammas.split(",")):
        for k in (float(v) for v in a.stiffness.split(",")):
            t_c = math.pi * math.sqrt(m_eff / k)
            implicit = a.dashpot == "implicit" and g * (t_c / 50) / m_eff > 0.2
            dt = t_c / 50 if a.dashpot == "implicit" else min(t_c / 50, m_eff / (5 * g))
            zeta = g / (2 * math.sqrt(k * m_eff))
            tt = t_agg(zeta)
            duration = a.end if tt is None else min(tt * a.t_ff, a.end)
            steps = duration / dt
            cpu = steps * a.seconds_per_step * (a.implicit_factor if implicit else 1.0)
            total += cpu * a.realizations
            print("%8.3g %8.3g %8.3g %10s %10.3g %8.0f" % (g, k, zeta, "none" if tt is None else "%.3g" % tt, steps, cpu))
    print("campaign: %d runs, %.0f CPU s = %.2f h; on %d ranks %.2f h" % (
        len(a.gammas.split(",")) * len(a.stiffness.split(",")) * a.realizations, total, total / 3600, a.ranks,
        total / 3600 / a.ranks))


if __name__ == "__main__":
    main()
