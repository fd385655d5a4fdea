#!/usr/bin/python3
"""bench/check against hand-made standings and figures: what counts as regressed, met, not run; exit codes;
the Markdown standing; --update. Standard library only (run by /usr/bin/python3 through CTest)."""
import csv
import os
import subprocess
import sys
import tempfile
import unittest

CHECK = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "bench", "check")
HEADER = "section,bench,case,figure,unit,better,target,reference,tolerance,anchor,command,date\n"


def run(*args):
    p = subprocess.run([sys.executable, CHECK, *args], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


class CheckTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.standing = os.path.join(self.dir.name, "standing.csv")
        self.figures = os.path.join(self.dir.name, "figures")
        os.mkdir(self.figures)
        with open(self.standing, "w") as f:
            f.write(HEADER)
            f.write('DSMC 10^6 in 8 s,dsmc,n=1e6,wall_seconds,s,lower,8,10,0.25,"Kalinov2022, Table 4",build/bench/x,2026-11-30\n')
            f.write("Elastic gas,ed,"",collisions_per_second,1/s,higher,2e5,1.5e5,0.2,reference code,build/bench/y,2026-11-30\n")
            f.write("Elastic gas,ed,3d,collisions_per_second,1/s,higher,,3e5,0.2,,build/bench/y,2026-11-30\n")

    def tearDown(self):
        self.dir.cleanup()

    def figures_file(self, rows):
        with open(os.path.join(self.figures, "f.csv"), "w") as f:
            f.write("date,bench,case,figure,value,unit,command\n")
            for r in rows:
                f.write(r + "\n")

    def test_within_noise_passes_and_reports_targets(self):
        self.figures_file(["2026-12-01T10:00:00Z,dsmc,n=1e6,wall_seconds,11,s,cmd",
                           "2026-12-01T10:00:00Z,ed,,collisions_per_second,2.1e5,1/s,cmd"])
        code, out, _ = run("--standing", self.standing, "--figures", self.figures)
        self.assertEqual(code, 0, out)
        self.assertIn("same, target missed", out)      # 11 s: 10 % worse than 10 s, tolerance 25 %; target 8 s
        self.assertIn("improved, target met", out)     # 2.1e5 vs 1.5e5, tolerance 20 %
        self.assertIn("not run", out)                  # the 3d row has no figure

    def test_worse_than_tolerance_is_a_regression_and_exits_1(self):
        self.figures_file(["2026-12-01T10:00:00Z,dsmc,n=1e6,wall_seconds,9,s,cmd",
                           "2026-12-01T11:00:00Z,dsmc,n=1e6,wall_seconds,13,s,cmd",  # the latest counts
                           "2026-12-01T10:00:00Z,ed,3d,collisions_per_second,2.3e5,1/s,cmd"])
        code, out, _ = run("--standing", self.standing, "--figures", self.figures)
        self.assertEqual(code, 1, out)
        self.assertIn("2 regressed", out)
        self.assertIn("dsmc [n=1e6] wall_seconds", out.split("regressed:")[-1])

    def test_nan_and_malformed_rows(self):
        self.figures_file(["2026-12-01T10:00:00Z,dsmc,n=1e6,wall_seconds,nan,s,cmd",
                           "2026-12-01T10:00:00Z,ed,,collisions_per_second,fast,1/s,cmd"])
        code, out, err = run("--standing", self.standing, "--figures", self.figures)
        self.assertEqual(code, 1, out)
        self.assertIn("regressed (nan)", out)
        self.assertIn("'fast' is not a number", err)

    def test_bad_standing_is_exit_2_naming_the_value(self):
        with open(self.standing, "a") as f:
            f.write("X,b,,f,s,smaller,,1,0,,c,d\n")
        code, _, err = run("--standing", self.standing, "--figures", self.figures)
        self.assertEqual(code, 2)
        self.assertIn("better = 'smaller': allowed: lower, higher", err)
        code, _, err = run("--standing", os.path.join(self.dir.name, "missing.csv"))
        self.assertEqual(code, 2)

    def test_same_flags_a_change_either_way(self):
        with open(self.standing, "a") as f:
            f.write("Hopf,hopf,a=0.9,lambda_crit,1,same,,0.00962,0.01,,c,d\n")
        self.figures_file(["2026-12-01T10:00:00Z,hopf,a=0.9,lambda_crit,0.00965,1,cmd"])
        code, out, _ = run("--standing", self.standing, "--figures", self.figures)
        self.assertEqual(code, 0, out)              # +0.3 %: within 1 %
        self.figures_file(["2026-12-01T10:00:00Z,hopf,a=0.9,lambda_crit,0.0095,1,cmd"])
        code, out, _ = run("--standing", self.standing, "--figures", self.figures)
        self.assertEqual(code, 1, out)              # -1.2 %
        self.assertIn("hopf [a=0.9] lambda_crit", out.split("regressed:")[-1])

    def test_a_zero_reference_regresses_on_any_count(self):
        with open(self.standing, "a") as f:
            f.write("Fuzz,fuzz,seed=7,findings,1,lower,0,0,0,,c,d\n")
        self.figures_file(["2026-12-01T10:00:00Z,fuzz,seed=7,findings,0,1,cmd"])
        self.assertEqual(run("--standing", self.standing, "--figures", self.figures)[0], 0)
        self.figures_file(["2026-12-01T10:00:00Z,fuzz,seed=7,findings,2,1,cmd"])
        code, out, _ = run("--standing", self.standing, "--figures", self.figures)
        self.assertEqual(code, 1, out)
        self.assertIn("regressed, target missed", out)

    def test_markdown_has_one_table_per_section(self):
        code, out, _ = run("--standing", self.standing, "--markdown")
        self.assertEqual(code, 0)
        self.assertEqual(out.count("### "), 2)
        self.assertIn("| wall_seconds [n=1e6] | 10 s | ≤ 8 s | Kalinov2022, Table 4 | `build/bench/x` | 2026-11-30 |", out)

    def test_update_takes_the_latest_figures(self):
        self.figures_file(["2026-12-01T10:00:00Z,dsmc,n=1e6,wall_seconds,7.5,s,build/bench/x 1000000"])
        code, out, _ = run("--standing", self.standing, "--figures", self.figures, "--update")
        self.assertEqual(code, 0, out)
        with open(self.standing, newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(rows[0]["reference"], "7.5")
        self.assertEqual(rows[0]["date"], "2026-12-01")
        self.assertEqual(rows[0]["command"], "build/bench/x 1000000")
        self.assertEqual(rows[1]["reference"], "1.5e5")  # not measured: unchanged
        code, out, _ = run("--standing", self.standing, "--figures", self.figures)
        self.assertEqual(code, 0, out)


class ResultsTest(unittest.TestCase):
    def test_results_md_shows_the_current_standing(self):
        """bench/results/RESULTS.md's tables are what bench/check --write-results makes of bench/results/standing.csv."""
        root = os.path.dirname(os.path.dirname(CHECK))
        with tempfile.TemporaryDirectory() as d:
            copy = os.path.join(d, "RESULTS.md")
            with open(os.path.join(root, "bench", "results", "RESULTS.md")) as f, open(copy, "w") as g:
                g.write(f.read())
            code, out, err = run("--results", copy, "--write-results")
            self.assertEqual(code, 0, err)
            self.assertIn("already current", out, "run bench/check --write-results after editing bench/results/standing.csv")
            for line in open(copy):  # every history link resolves
                if "](log/" in line:
                    target = line.split("](", 1)[1].split(")", 1)[0]
                    self.assertTrue(os.path.exists(os.path.join(root, "bench", "results", target)), target)


if __name__ == "__main__":
    unittest.main()
