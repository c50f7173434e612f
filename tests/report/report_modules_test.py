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
from trajectory import advice, lines
from view3d import bounds_of, grid_step, length_words, script_json
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
                self.assertEqual(item.text, "a&<b.motion.h5:/segments")
            else:
                self.assertIsNone(written)
                self.assertIn("has a ':'", why)

    def motion_file(self, frames=3):
        def build(f):
            f["time"] = np.linspace(0.0, 1.0, frames)
            f["motion/points"] = np.arange(frames * 4 * 3, dtype=float).reshape(frames, 4, 3) / 7
            f["motion/segments"] = np.array([[0, 1], [1, 2], [2, 3]])
        write(self.path, build)
        with open(self.path, "rb") as f:
            return f.read()

    def test_xdmf_steps_read_in_meshio_one_by_one_and_the_trajectory_file_is_untouched(self):
        from meshio.xdmf import TimeSeriesReader
        before = self.motion_file()
        with h5py.File(self.path) as f:
            written, why = write_xdmf(f, self.path)
            points = f["motion/points"][:]
        self.assertEqual(written, os.path.join(self.dir.name, "e.xmf"), why)
        with open(written, encoding="utf-8") as x:
            self.assertNotIn("HyperSlab", x.read())  # ParaView's Xdmf3 readers and meshio read none
        with TimeSeriesReader(written) as reader:
            first, cells = reader.read_points_cells()
            np.testing.assert_array_equal(first, points[0])
            self.assertEqual(cells[0].type, "line")
            np.testing.assert_array_equal(cells[0].data, [[0, 1], [1, 2], [2, 3]])
            self.assertEqual(reader.num_steps, 3)
            for k in range(3):
                t, point_data, _ = reader.read_data(k)
                self.assertEqual(t, 0.5 * k)
                np.testing.assert_array_equal(point_data["position"], points[k])
        with h5py.File(os.path.join(self.dir.name, "e.motion.h5")) as c:
            self.assertEqual(c.attrs["written_by"], "treedyn report")
            self.assertEqual(c.attrs["source"], "e.h5")
        with open(self.path, "rb") as f:
            self.assertEqual(f.read(), before)
        with h5py.File(self.path) as f:  # a second report replaces its own companion
            self.assertIsNotNone(write_xdmf(f, self.path)[0])

    def test_xdmf_never_replaces_a_file_it_did_not_write(self):
        self.motion_file()
        companion = os.path.join(self.dir.name, "e.motion.h5")
        for content in (b"someone's notes\n", None):
            if content is None:
                with h5py.File(companion, "w") as other:  # HDF5, but another run's output
                    other["time"] = np.zeros(2)
            else:
                with open(companion, "wb") as other:
                    other.write(content)
            with open(companion, "rb") as other:
                kept = other.read()
            with h5py.File(self.path) as f:
                written, why = write_xdmf(f, self.path)
            self.assertIsNone(written)
            self.assertEqual(why, f"{companion} exists and was not written by treedyn report")
            with open(companion, "rb") as other:
                self.assertEqual(other.read(), kept)
            os.remove(companion)
        self.assertFalse(os.path.exists(os.path.join(self.dir.name, "e.xmf")))

    def test_an_xdmf_file_that_cannot_be_written_leaves_no_companion(self):
        self.motion_file()
        os.mkdir(os.path.join(self.dir.name, "e.xmf"))
        with h5py.File(self.path) as f:
            written, why = write_xdmf(f, self.path)
        self.assertIsNone(written)
        self.assertTrue(why.startswith(f"cannot write {os.path.join(self.dir.name, 'e.xmf')} ("), why)
        self.assertEqual(sorted(os.listdir(self.dir.name)), ["e.h5", "e.xmf"])

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


class FailedSample(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.path = os.path.join(self.dir.name, "s.h5")
        with h5py.File(self.path, "w") as f:
            f.attrs["relative_tolerance"], f.attrs["absolute_tolerance"] = 1e-8, 1e-10
            f.attrs["job_text"] = "[integrator]\nmethod = \"erk_dormand_prince\"\nmax_steps = 200\n"
            f.attrs["command_line"] = "treedyn-ensemble job.toml --sample 6 -o s.h5"

    def tearDown(self):
        self.dir.cleanup()

    def test_what_to_change_follows_the_failure(self):
        with h5py.File(self.path) as f:
            self.assertEqual(advice(f, "too_much_work at t = 0.07 s: 200 steps (max_steps) taken"),
                             "What to change: raise [integrator] max_steps (200 steps per output interval here), "
                             "loosen the tolerances (rtol = 1e-08, atol = 1e-10), or check the model. Then rerun "
                             "this sample: treedyn-ensemble job.toml --sample 6 -o s.h5")
            self.assertTrue(advice(f, "too_much_accuracy at t = 0 s").startswith(
                "What to change: loosen the tolerances (rtol = 1e-08, atol = 1e-10): they ask for more"))
            self.assertTrue(advice(f, "something new at t = 1 s").startswith(
                "What to change: loosen the tolerances (rtol = 1e-08, atol = 1e-10), raise [integrator] max_steps, "
                "or check the model."))
        with h5py.File(self.path, "a") as f:
            del f.attrs["job_text"]  # treedyn's default then
            self.assertIn("max_steps (100000 steps per output interval here)", advice(f, "too_much_work at t = 1 s"))

    def test_time_plots_mark_the_failure(self):
        class Keep:
            def figure(self, fig, caption, name):
                self.fig, self.caption = fig, caption

        page = Keep()
        lines(page, np.array([0.0, 0.1]), np.array([[1.0], [2.0]]), ["rod.angle"], "angle (rad)", "joint angles",
              "joint_angles", failed=0.1875)
        ax = page.fig.axes[0]
        marks = [line for line in ax.get_lines() if list(line.get_xdata()) == [0.1875, 0.1875]]
        self.assertEqual(len(marks), 1)
        self.assertEqual([t.get_text() for t in ax.texts], ["failed at t = 0.1875 s "])
        self.assertEqual(page.caption, "joint angles; the red dashed line: failed at t = 0.1875 s")
        self.assertGreaterEqual(ax.get_xlim()[1], 0.1875)  # the line is inside the plot
        lines(page, np.array([0.0, 0.1]), np.array([[1.0], [2.0]]), ["rod.angle"], "angle (rad)", "joint angles",
              "joint_angles")
        self.assertEqual((len(page.fig.axes[0].get_lines()), page.caption), (1, "joint angles"))


class Readings(unittest.TestCase):
    def test_view_json_cannot_close_or_reopen_its_script_element(self):
        text = script_json({"title": "</script><!--<script>&", "x": [1.5]})
        for bad in ("<", ">", "&"):
            self.assertNotIn(bad, text)
        import json
        self.assertEqual(json.loads(text)["title"], "</script><!--<script>&")
        with self.assertRaises(ValueError):
            script_json({"x": [float("nan")]})  # JSON.parse refuses NaN: the view turns them into null first

    def test_view_bounds_hold_turned_shapes_and_joints(self):
        c, s = math.cos(math.pi / 4), math.sin(math.pi / 4)  # half angles of quarter turns
        scene = {"shapes": ["box", "cylinder", "sphere", "none"],
                 "dimensions": [[2.0, 4.0, 6.0], [0.5, 0.5, 4.0], [1.0, 1.0, 1.0], [0.0, 0.0, 0.0]],
                 "com_to_joint": [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 9.0]]}
        pose = np.array([[0, 0, 0, c, 0, 0, s,  # the box turned a quarter about z: 4 x 2 x 6
                          10, 0, 0, c, 0, s, 0,  # the cylinder turned a quarter about y: its length along x
                          0, 20, 0, 1, 0, 0, 0,
                          0, 0, -5, 1, 0, 0, 0]])  # no shape; its joint 9 m above its CoM
        low, high = bounds_of(scene, [pose, pose + np.r_[0, 0, 2, np.zeros(25)]])  # a run whose box is 2 m higher
        np.testing.assert_allclose(low, [-2, -1, -5], atol=1e-6)
        np.testing.assert_allclose(high, [12, 21, 5], atol=1e-6)
        self.assertEqual(grid_step(np.zeros(3), np.array([12.0, 16.0, 5.0])), 2)  # 20.6 m across: a twelfth 1.7 m
        self.assertEqual(grid_step(np.zeros(3), np.array([0.6, 0.0, 0.8])), 0.1)
        self.assertEqual([length_words(v) for v in (2.0, 0.5, 0.1, 0.005)], ["2 m", "50 cm", "10 cm", "5 mm"])

    def test_rotation_angle_of_quaternions(self):
        q0 = np.cos(np.radians([0.0, 45.0, 90.0]))  # rotations by 0, 90 and 180 degrees
        np.testing.assert_allclose(rotation_angle_degrees(q0), [0.0, 90.0, 180.0], atol=1e-9)

    def test_valid_ranges(self):
        self.assertEqual(valid_range("joint_angle", "rod.angle"), (0.0, math.pi))
        self.assertEqual(valid_range("energy", "kinetic"), (0.0, math.inf))
        self.assertEqual(valid_range("energy", "total"), (-math.inf, math.inf))


if __name__ == "__main__":
    unittest.main()
