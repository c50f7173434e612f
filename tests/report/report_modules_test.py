#!/usr/bin/python3
"""Unit tests of the report's answers and readings (src/report/), each against a value worked out by hand
or a synthetic file whose answer is known. Run by ctest (ReportModules)."""
import math
import os
import tempfile
import unittest

import h5py
import numpy as np

from answers import (asked_pair, conclusion, driver_order, group_drivers, input_correlations, last_time_warnings,
                     mean_verdict, outside_range_warnings, probability_verdict)
from history import constant_columns, rotation_angle_degrees, valid_range
from read import counted_rows
from view3d import script_json
from xdmf import write_xdmf


class Verdicts(unittest.TestCase):
    def test_mean_enough_and_how_many_runs_otherwise(self):
        self.assertTrue(mean_verdict(10.0, 0.1, 100).startswith("yes: ±2.0%"))
        # sigma = 1 * sqrt(100) = 10; n >= (1.96 * 10 / (0.05 * 10))^2 = 1536.64
        self.assertIn("about 1537 counted runs", mean_verdict(10.0, 1.0, 100))
        self.assertTrue(mean_verdict(10.0, 1.0, 5).startswith("no: 5 runs"))
        # 12 finite values of 128 runs (the others never crossed): the runs to count scale by 128 / 12.
        self.assertIn(f"about {math.ceil(128 / 12 * 1536.64)} counted runs", mean_verdict(10.0, 1.0, 100, 128 / 12))
        self.assertTrue(mean_verdict(0.0, 100.0, 50).startswith("no relative precision (the mean is 0)"))

    def test_probability(self):
        self.assertIn("no exceedance in 200 runs: P < 0.019", probability_verdict(0, 200, 0.0, 0.0, 0.0188))
        self.assertTrue(probability_verdict(400, 1000, 0.4, 0.37, 0.43).startswith("yes: ±8%"))
        # half-width 0.05 of P = 0.1: 50 %; runs for 20 %: 100 * (0.5 / 0.2)^2 = 625
        self.assertIn("about 625 counted runs", probability_verdict(10, 100, 0.1, 0.05, 0.15))
        self.assertEqual(probability_verdict(0, 0, float("nan"), 0.0, 1.0), "no successful run")


def write(path, build):
    with h5py.File(path, "w") as f:
        build(f)


class FromFiles(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.path = os.path.join(self.dir.name, "e.h5")

    def tearDown(self):
        self.dir.cleanup()

    def test_saltelli_counts_a_and_b_rows_only(self):
        def build(f):
            f.attrs["design"], f.attrs["saltelli_block"] = "saltelli", 4  # D = 2
            f["samples/status"] = np.zeros(12, dtype=np.int32)
        write(self.path, build)
        with h5py.File(self.path) as f:
            rows, words = counted_rows(f)
        self.assertEqual(list(np.flatnonzero(rows)), [0, 1, 4, 5, 8, 9])
        self.assertIn("6 independent runs of the 12", words)

    def test_correlated_inputs_are_found_and_independent_ones_not(self):
        rng = np.random.default_rng(1)
        a, c = rng.uniform(size=2000), rng.uniform(size=2000)
        b = a + 0.1 * rng.normal(size=2000)  # Spearman about 0.94 with a

        def build(f):
            f["samples/status"] = np.zeros(2000, dtype=np.int32)
            f["samples/inputs"] = np.column_stack([a, b, c])
            f["samples/inputs"].attrs["columns"] = ["a", "b", "c"]
        write(self.path, build)
        with h5py.File(self.path) as f:
            pairs, names, n = input_correlations(f, np.ones(2000, dtype=bool))
        self.assertEqual(n, 2000)
        self.assertEqual(sorted(pairs), [0, 1])
        self.assertGreater(pairs[0][0][1], 0.9)

    def test_a_maximum_at_the_last_output_time_is_flagged(self):
        def build(f):
            f["stats/time"] = np.linspace(0, 10, 11)
            r = f.create_dataset("samples/responses", data=np.zeros((10, 2)))
            r.attrs["columns"] = ["late", "early"]
            r.attrs["reduce"] = ["max", "max"]
            r.attrs["quantity"] = ["joint_angle", "joint_angle"]
            r.attrs["column"] = ["a.angle", "b.angle"]
            t = f.create_dataset("samples/argmax_time/joint_angle",
                                 data=np.column_stack([np.full(10, 10.0), np.r_[np.full(9, 3.0), 10.0]]))
            t.attrs["columns"] = ["a.angle", "b.angle"]
        write(self.path, build)
        with h5py.File(self.path) as f:
            warnings = last_time_warnings(f, np.ones(10, dtype=bool))
        self.assertEqual(len(warnings), 1)  # 'early' reaches it in 1 of 10 runs, not more than 10 %
        self.assertTrue(warnings[0].startswith("late: in 10 of 10 runs the maximum"))

    def test_rows_a_merge_does_not_hold_are_not_counted(self):
        def build(f):
            f["samples/status"] = np.array([0, 1, 3, 3, 0], dtype=np.int32)
        write(self.path, build)
        with h5py.File(self.path) as f:
            rows, words = counted_rows(f)
        self.assertEqual(list(np.flatnonzero(rows)), [0, 1, 4])
        self.assertEqual(words, "all 3 samples, of the 3 this merged file holds")

    def test_xdmf_names_are_escaped_and_a_colon_refused(self):
        for name, ok in (("a&<b.h5", True), ("a:b.h5", False)):
            path = os.path.join(self.dir.name, name)

            def build(f):
                f["time"] = np.array([0.0, 0.5])
                f["motion/points"] = np.zeros((2, 2, 3))
                f["motion/segments"] = np.array([[0, 1]])
            write(path, build)
            with h5py.File(path) as f:
                written, why = write_xdmf(f, path)
            if ok:
                import xml.etree.ElementTree as ET
                item = ET.parse(written).getroot().find("Domain/Grid/Grid/Topology/DataItem")
                self.assertEqual(item.text, "a&<b.h5:/motion/segments")
            else:
                self.assertIsNone(written)
                self.assertIn("has a ':'", why)

    def test_normal_mass_below_zero(self):
        def build(f):
            d = f.create_dataset("samples/inputs", data=np.zeros((1, 3)))
            d.attrs["columns"] = ["body.tip.mass", "base.z[1].amplitude", "body.rod.mass"]
            d.attrs["column_distributions"] = ["normal(mean=1, std=1)", "normal(mean=0, std=1)",
                                               "normal(mean=0, std=0.05)"]
            d.attrs["column_modes"] = ["set", "set", "add"]  # an offset of the nominal mass may be negative
        write(self.path, build)
        with h5py.File(self.path) as f:
            warnings = outside_range_warnings(f)
        self.assertEqual(len(warnings), 1)
        self.assertIn(f"P = {0.5 * math.erfc(1 / math.sqrt(2)):.2g}", warnings[0])  # Phi(-1) = 0.16

    def test_constant_columns(self):
        def build(f):
            f["stats/q/min"] = np.array([[0.0, 1.0], [0.0, 0.5]])
            f["stats/q/max"] = np.array([[0.0, 2.0], [0.0, 2.5]])
        write(self.path, build)
        with h5py.File(self.path) as f:
            self.assertEqual(constant_columns(f["stats/q"]), {0})

    def test_drivers_sentence(self):
        def build(f):
            f["s/total_order"] = np.array([0.01, 0.9])
            f["s/srrc"] = np.array([0.1, 0.9])
        write(self.path, build)
        with h5py.File(self.path) as f:
            words = conclusion("y", f["s"], [1, 0], ["a", "b"])
        self.assertEqual(words, "y is driven by b (total Sobol' index 0.9); a matter little (total Sobol' index "
                                "below 0.05).")


    def test_a_grouped_design_ranks_groups_by_their_indices_and_inputs_by_srrc(self):
        def build(f):
            f["s/total_order"] = np.array([np.nan, np.nan, 0.02])  # inputs 0 and 1 are one group
            f["s/srrc"] = np.array([0.1, 0.8, 0.05])
            f["s/group_total_order"] = np.array([0.97, 0.02])
            f["s/group_total_order"].attrs["columns"] = ["start", "c"]
            f["s/group_first_order"] = np.array([0.95, 0.01])
            f["s/group_total_order_ci"] = np.array([[0.9, 1.0], [0.0, 0.05]])
            f["s/group_first_order_ci"] = np.array([[0.9, 1.0], [0.0, 0.04]])
            f["s"].attrs["group_inputs"] = ["a, b", "c"]
        write(self.path, build)

        class Collect:
            def __init__(self):
                self.notes, self.tables = [], []

            def note(self, words, kind="warning"):
                self.notes.append(words)

            def table(self, header, rows, code_columns=()):
                self.tables.append(rows)

        page = Collect()
        with h5py.File(self.path) as f:
            self.assertEqual(list(driver_order(f["s"])), [1, 0, 2])  # by |SRRC|: the Sobol' ones are per group
            group_drivers(page, "y", f["s"])
        self.assertEqual(page.notes, ["y is driven by start (total Sobol' index 0.97); c matter little (total "
                                      "Sobol' index below 0.05) (groups: the inputs of each taken together)."])
        self.assertEqual([row[:2] for row in page.tables[0]], [["start", "a, b"], ["c", "c"]])

    def test_asked_pairs_are_matched_by_name_not_by_substring(self):
        asked = ["body.a.mass ~ body.b.mass: normal copula 0.5, Spearman 0.48"]
        self.assertTrue(asked_pair(asked, "body.b.mass", "body.a.mass"))
        self.assertFalse(asked_pair(asked, "body.a.mas", "body.b.mass"))


class Readings(unittest.TestCase):
    def test_view_json_cannot_close_or_reopen_its_script_element(self):
        text = script_json({"title": "</script><!--<script>&", "x": [1.5]})
        for bad in ("<", ">", "&"):
            self.assertNotIn(bad, text)
        import json
        self.assertEqual(json.loads(text)["title"], "</script><!--<script>&")
        with self.assertRaises(ValueError):
            script_json({"x": [float("nan")]})  # JSON.parse refuses NaN: the view turns them into null first

    def test_rotation_angle_of_quaternions(self):
        q0 = np.cos(np.radians([0.0, 45.0, 90.0]))  # rotations by 0, 90 and 180 degrees
        np.testing.assert_allclose(rotation_angle_degrees(q0), [0.0, 90.0, 180.0], atol=1e-9)

    def test_valid_ranges(self):
        self.assertEqual(valid_range("joint_angle", "rod.angle"), (0.0, math.pi))
        self.assertEqual(valid_range("energy", "kinetic"), (0.0, math.inf))
        self.assertEqual(valid_range("energy", "total"), (-math.inf, math.inf))


if __name__ == "__main__":
    unittest.main()
