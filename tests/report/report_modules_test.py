#!/usr/bin/python3
"""Unit tests of the report's answers and readings (src/report/), each against a value worked out by hand
or a synthetic file whose answer is known. Run by ctest (ReportModules)."""
import math
import os
import tempfile
import unittest

import h5py
import numpy as np

from answers import (extreme_samples, integration_verdicts, failure_effects,
                     last_time_warnings, mean_verdict, outside_range_warnings, probability_verdict, response_row,
                     scatter_figures)
from drivers import asked_pair, disagreement_note, drivers_section, input_correlations
from ensemble_details import response_figures, sensitivity_figures
from failure_region import failure_region_section
from history import constant_columns, rotation_angle_degrees, valid_range
from designs import counted_rows, design_of
from designs.morris import morris_figures
from designs.saltelli import first_order_cell, index_figures, index_notes, index_verdict, own_measure_words
from rankings import Ranking, chain, driven_by, primary_ranking, visible_units
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


class IntegrationCheck(unittest.TestCase):
    def test_each_response_gets_the_files_verdict_and_a_loose_one_an_alarm(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "e.h5")
            with h5py.File(path, "w") as f:
                g = f.create_group("integration_check")
                g.attrs["verdicts"] = ["enough: its change ...", "too loose for this answer: its change is 0.5 ..."]
            with h5py.File(path) as f:
                self.assertEqual(integration_verdicts(f)[1], "too loose for this answer: its change is 0.5 ...")
            with h5py.File(path, "w") as f:
                f.create_group("samples")
            with h5py.File(path) as f:
                self.assertEqual(integration_verdicts(f), [], "an older file without the check")


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
            pairs, n = input_correlations(f, np.ones(2000, dtype=bool))
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

    def test_a_design_is_found_by_its_name(self):
        """Every name treedyn writes (sampling/design.hpp) has its module or base.py's; so do a name this report
        does not know and one that is not a module name."""
        for name, module in (("saltelli", "designs.saltelli"), ("morris", "designs.morris"),
                             ("subset_simulation", "designs.subset_simulation"), ("sobol", "designs.sobol"),
                             ("latin_hypercube", "designs.latin_hypercube"), ("monte_carlo", "designs.base"),
                             ("importance_sampling", "designs.base"), ("../answers", "designs.base"),
                             ("base", "designs.base"), ("__init__", "designs.base"), ("Saltelli", "designs.base")):
            with h5py.File(self.path, "w") as f:
                f.attrs["design"] = name
                self.assertEqual(design_of(f).module.__name__, module, name)
                # a hook the module does not define is base.py's
                self.assertTrue(callable(design_of(f).after_failure_region), name)
        with h5py.File(self.path, "w") as f:
            self.assertEqual(design_of(f).module.__name__, "designs.base")  # no design attribute
            f["samples/level"] = np.zeros(4, dtype=np.int32)  # ... but levels: read as subset simulation
            self.assertEqual(design_of(f).module.__name__, "designs.subset_simulation")

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
        self.assertEqual(valid_range("com_offset", "container.horizontal"), (0.0, math.inf))
        self.assertEqual(valid_range("com_offset", "container.y"), (-math.inf, math.inf))

class Collect:
    """A page that keeps what the report would write, for the tests to read."""
    def __init__(self):
        self.parts, self.figures = [], []

    def heading(self, words, level=2):
        self.parts.append(("heading", words))

    def paragraph(self, words):
        self.parts.append(("paragraph", words))

    def note(self, words, kind="warning"):
        self.parts.append((kind, words))

    def table(self, header, rows, code_columns=()):
        self.parts.append(("table", (header, rows)))

    def figure(self, fig, caption, name):
        self.figures.append((fig, caption, name))
        self.parts.append(("figure", caption))

    def words(self, kind=None):
        return [w for k, w in self.parts if (kind is None or k == kind) and isinstance(w, str)]

    def tables(self):
        return [w for k, w in self.parts if k == "table"]


def ranking(value, ci, order, told_apart, needed, units=None, resamples=1000, members=None):
    units = units or [chr(ord("A") + i) for i in range(len(value))]
    return Ranking("total Sobol' index", units, members or [[i] for i in range(len(units))], np.array(value, float),
                   np.array(ci, float), np.array(order), np.array(told_apart, bool), np.array(needed, float),
                   resamples, "base points")


class Rankings(unittest.TestCase):
    def test_an_order_only_where_told_apart_and_how_many_would_tell_the_rest(self):
        r = ranking([0.84, 0.3, 0.25, 0.01], [[0.6, 1.2], [0.02, 0.6], [-0.1, 0.6], [0.0, 0.04]], [0, 1, 2, 3],
                    [1, 0, 1], [np.nan, 2261.6, np.nan])
        self.assertEqual(driven_by("y", r, [0, 1, 2, 3], "from 16 of 16 base points"),
                         "y is driven by A 0.84 [0.6, 1] > B 0.3 [0.02, 0.6] ~ C 0.25 [0, 0.6] (total Sobol' index "
                         "[95 %], from 16 of 16 base points). B and C cannot yet be told apart (about 2262 base "
                         "points would tell them apart). D matters little (the 95 % interval of the total Sobol' "
                         "index ends below 0.05).")

    def test_negligible_only_where_the_interval_ends_below_5_percent(self):
        r = ranking([0.9, 0.03, 0.02], [[0.8, 1.0], [0.0, 0.08], [0.0, 0.049]], [0, 1, 2], [1, 0], [np.nan, 50.0])
        words = driven_by("y", r, [0, 1, 2], "w")
        self.assertIn("A 0.9 [0.8, 1] > B 0.03 [0, 0.08] (", words)  # its estimate is small, its interval not
        self.assertIn("C matters little", words)
        self.assertNotIn("B matters little", words)

    def test_units_left_out_between_two_shown_ones_carry_their_told_apart_pairs(self):
        # order A, p1, p2, B, p3, C: A > p1 told apart, so A > B; nothing between B and C is: B ~ C, and the
        # least of the pairs between them is what would tell them apart
        r = ranking([0.9, 0.5, 0.4, 0.3, 0.2, 0.1], np.tile([0.06, 1.0], (6, 1)), [0, 3, 4, 1, 5, 2],
                    [1, 0, 0, 0, 0], [np.nan, 900.0, 800.0, 700.0, np.inf], units=["A", "B", "C", "p1", "p2", "p3"])
        links = chain(r, [0, 1, 2])
        self.assertEqual([(link.unit, link.apart) for link in links], [(0, True), (1, True), (2, False)])
        self.assertEqual(links[2].needed, 700.0)
        self.assertTrue(driven_by("y", r, [0, 1, 2], "w").startswith("y is driven by A 0.9 [0.06, 1] > B 0.5 "
                                                                     "[0.06, 1] ~ C 0.4 [0.06, 1]"))

    def test_equal_measures_and_no_bootstrap(self):
        r = ranking([0.5, 0.5], [[0.4, 0.6], [0.4, 0.6]], [0, 1], [0], [np.inf])
        self.assertIn("A and B cannot yet be told apart (their estimates are equal: more base points would not tell "
                      "them apart).", driven_by("y", r, [0, 1], "w"))
        bare = ranking([0.5, 0.2], np.full((2, 2), np.nan), [0, 1], [0], [np.nan], resamples=0)
        self.assertEqual(driven_by("y", bare, [0, 1], "w"), "y is driven by A 0.5, B 0.2 (total Sobol' index, w). No "
                         "bootstrap intervals (bootstrap_resamples = 0): the order is the estimates' alone.")

    def test_first_order_above_total_is_within_noise_only_where_the_intervals_overlap(self):
        self.assertEqual(first_order_cell(0.298, [0.0078, 0.655], 0.214, [0.06, 0.63]),
                         "0.298 [0.0078, 0.655]: within noise of the total")
        self.assertEqual(first_order_cell(0.9, [0.8, 1.2], 0.3, [0.2, 0.4]),
                         "0.9 [0.8, 1]: above the total beyond the intervals")
        self.assertEqual(first_order_cell(0.1, [-0.2, 0.3], 0.2, [0.1, 0.3]), "0.1 [0, 0.3]")
        r = ranking([0.214, 0.3, 1.07], [[0.06, 0.63], [0.2, 0.4], [0.78, 1.3]], [2, 1, 0], [0, 0], [10.0, 10.0],
                    units=["phases", "mass", "Hs"])
        notes = index_notes(r, [0, 1, 2], np.array([0.298, 0.9, 0.6]), np.array([[0.0078, 0.655], [0.8, 1.2],
                                                                                   [0.3, 0.9]]))
        self.assertEqual(len(notes), 3)
        self.assertTrue(notes[0].startswith("First order above total (phases): within noise. Where an input does "
                                            "not interact, both estimate the same share of variance"))
        self.assertTrue(notes[1].startswith("First order above total beyond their intervals (mass)"))
        self.assertTrue(notes[2].startswith("An estimate outside [0, 1] (Hs 1.1) is estimation noise"))

    def test_one_note_where_the_rank_measure_puts_another_input_first(self):
        sobol = ranking([0.7, 0.3, 0.1], [[0.3, 1], [0.1, 0.6], [0.06, 0.2]], [2, 1, 0], [0, 0], [10.0, 10.0],
                        units=["Hs", "mass", "sea phases"], members=[[0], [1], [2, 3, 4, 5]])
        ranks = ranking([0.35, 0.09, 0.1, 0.1, 0.1, 0.1], np.tile([0.0, 1.0], (6, 1)), [0, 2, 1, 3, 4, 5],
                        [0] * 5, [np.nan] * 5, units=["Hs", "mass", "p1", "p2", "p3", "p4"])
        ranks = ranks._replace(measure="|Spearman|", word="runs")
        note = disagreement_note("swing", sobol, [0, 1, 2], ranks, [0, 1], own_measure_words())
        self.assertTrue(note.startswith("swing: the rank measures put another input first: Hs 0.35 [0, 1] by "
                                        "|Spearman|, sea phases 0.1 [0.06, 0.2] by the total Sobol' index. They "
                                        "measure different things: |Spearman| how monotonically"), note)
        self.assertIn("sea phases is a group", note)
        same = sobol._replace(order=np.array([0, 1, 2]))
        self.assertEqual(disagreement_note("swing", same, [0, 1, 2], ranks, [0, 1], own_measure_words()), "")


def sensitivity_group(f, name, total, ci, order, told, needed, **attrs):
    """A saltelli response's /sensitivity group over the inputs of saltelli_file."""
    s = f.create_group(f"sensitivity/{name}")
    d = len(total)
    s["total_order"], s["total_order_ci"] = np.array(total, float), np.array(ci, float)
    s["first_order"], s["first_order_ci"] = np.array(total, float) * 0.9, np.array(ci, float) * 0.9
    s["spearman"], s["srrc"] = np.linspace(0.9, 0.1, d), np.full(d, np.nan)
    s["spearman"].attrs["columns"] = ["a", "b"][:d]
    s["rank_measure_ci"] = np.tile([0.0, 1.0], (d, 1))
    for key, measure, k in (("sobol_ranking", "total Sobol' index", order), ("rank_ranking", "|Spearman|", range(d))):
        g = s.create_group(key)
        g.attrs["measure"], g.attrs["resamples"] = measure, 1000
        g["order"], g["told_apart"] = np.array(list(k)), np.array(told)
        g["needed"], g["difference_ci"] = np.array(needed, float), np.zeros((d - 1, 2))
    s.attrs.update({"sobol_blocks": 16, "sobol_base_samples": 16, "sobol_reliable": 1, "rank_samples": 32,
                    "rank_r_squared": np.nan, "index_widest_interval": 0.57, "index_widest_unit": "b",
                    "index_base_points_needed": 526.0, "indices_enough": 0, **attrs})
    return s


def saltelli_file(f, blocks=4, big_ab=None, limit=25.0):
    """Two inputs (a in kg, b in m), one response y (N) with a limit, a Saltelli design (block of 4: A, B,
    AB_1, AB_2); `big_ab`: a value given to the first AB run, beyond every counted one."""
    n = 4 * blocks
    f.attrs["design"], f.attrs["saltelli_block"] = "saltelli", 4
    f["samples/status"] = np.zeros(n, dtype=np.int32)
    rng = np.random.default_rng(3)
    x = rng.uniform(size=(n, 2))
    f["samples/inputs"] = x
    f["samples/inputs"].attrs.update({"columns": ["a", "b"], "column_units": ["kg", "m"],
                                      "column_targets": ["a", "b"]})
    y = 20 + 10 * x[:, 0]
    if big_ab is not None:
        y[2] = big_ab
    r = f.create_dataset("samples/responses", data=y[:, None])
    r.attrs.update({"columns": ["y"], "column_units": ["N"], "limit": [limit], "fail_if": ["above"]})
    f.create_dataset("samples/reason", data=[""] * n, dtype=h5py.string_dtype())
    return y


class FromAnswerFiles(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.path = os.path.join(self.dir.name, "e.h5")

    def tearDown(self):
        self.dir.cleanup()

    def test_the_sobol_ranking_is_the_primary_one_where_there_is_one(self):
        def build(f):
            saltelli_file(f)
            sensitivity_group(f, "y", [0.2, 0.8], [[0.1, 0.3], [0.6, 1.1]], [1, 0], [1], [np.nan])
            del f["sensitivity/y/total_order"]  # a Monte-Carlo design: the rank measure ranks
            del f["sensitivity/y/total_order_ci"]
        write(self.path, build)
        with h5py.File(self.path, "a") as f:
            self.assertEqual(primary_ranking(f["sensitivity/y"], ["a", "b"]).measure, "|Spearman|")
            f["sensitivity/y/total_order"] = np.array([0.2, 0.8])
            f["sensitivity/y/total_order_ci"] = np.array([[0.1, 0.3], [0.6, 1.1]])
            r = primary_ranking(f["sensitivity/y"], ["a", "b"])
            self.assertEqual((r.measure, list(r.order), r.word), ("total Sobol' index", [1, 0], "base points"))
            page = Collect()
            drivers_section(f, page, counted_rows(f)[0])
        self.assertEqual(page.words("good"), ["y is driven by b 0.8 [0.6, 1] > a 0.2 [0.1, 0.3] (total Sobol' index "
                                              "[95 %], from 16 of 16 base points)."])
        self.assertIn("No rank regression (SRRC, R²): it needs more runs than inputs (2 inputs, 32 runs), or an "
                      "input or the response is constant; the rank measure is then Spearman's.", page.words())

    def test_a_list_s_entries_are_not_ranked_one_by_one_but_a_group_is(self):
        names = ["a", "b"] + [f"p[{k}]" for k in range(1, 5)]

        def build(f):
            f["samples/inputs"] = np.zeros((4, 6))
            f["samples/inputs"].attrs.update({"columns": names, "column_targets": ["a", "b"] + ["p"] * 4})
        write(self.path, build)
        per_input = ranking(np.linspace(0.9, 0.1, 6), np.tile([0.06, 1.0], (6, 1)), [2, 0, 3, 1, 4, 5], [1] * 5,
                            [np.nan] * 5, units=names)
        grouped = per_input._replace(units=["a", "b", "p"], members=[[0], [1], [2, 3, 4, 5]])
        with h5py.File(self.path) as f:
            self.assertEqual(visible_units(per_input, f["samples/inputs"]), [0, 1])
            self.assertEqual(visible_units(grouped, f["samples/inputs"]), [0, 1, 2])

    def test_the_verdict_on_n_for_the_indices(self):
        def build(f):
            f.create_group("s")
        write(self.path, build)
        with h5py.File(self.path, "a") as f:
            s = f["s"]
            self.assertEqual(index_verdict(s), "")  # not a saltelli design
            s.attrs.update({"sobol_blocks": 16, "sobol_base_samples": 16, "sobol_reliable": 1,
                            "index_widest_interval": 0.57, "index_widest_unit": "sea phases",
                            "index_base_points_needed": 526.0, "indices_enough": 0})
            self.assertEqual(index_verdict(s), "not for 0.1: the widest total-index interval of an input that "
                                                "matters is 0.57 (sea phases); about 526 base points would do (from "
                                                "16 of 16 base points)")
            s.attrs.update({"index_widest_interval": 0.08, "indices_enough": 1})
            self.assertTrue(index_verdict(s).startswith("yes: the widest total-index interval of an input that "
                                                        "matters is 0.08 (sea phases)"))
            s.attrs.update({"sobol_base_samples": 7, "sobol_reliable": 0})
            self.assertTrue(index_verdict(s).startswith("no: unreliable, failed runs left 7 of 16 base points "
                                                        "complete (fewer than 80 %)"), index_verdict(s))

    def failing_file(self, f):
        y = saltelli_file(f)
        f["samples/status"][5] = 1
        f["responses/y/exceedance/probability"], f["responses/y/exceedance/failed"] = 3 / 29, 3
        f["responses/y/exceedance/successful"], f["responses/y/exceedance/count"] = 29, 3
        f["responses/y/exceedance/interval"] = np.array([0.0358, 0.264])
        f["responses/y/exceedance/with_failed"] = np.array([0.09375, 0.1875])
        for key, v in (("mean", 22.0), ("sem", 0.4), ("used", 29), ("failed", 3), ("not_finite", 0)):
            f[f"responses/y/{key}"] = v
        sensitivity_group(f, "y", [0.2, 0.8], [[0.1, 0.3], [0.6, 1.1]], [1, 0], [1], [np.nan],
                          sobol_base_samples=7, sobol_reliable=0)
        return y

    def test_what_the_failed_runs_change_is_said_first(self):
        write(self.path, self.failing_file)
        with h5py.File(self.path) as f:
            effects = failure_effects(f)
            row = response_row(f, f["samples/responses"], 0, "y", "N")
            page = Collect()
            drivers_section(f, page, counted_rows(f)[0])
        self.assertEqual(effects, ["P(y > 25 N) = 0.1034 rests on 29 of 32 counted runs; with the 3 failed ones "
                                   "counted as not exceeding or as exceeding it would be 0.09375 to 0.1875.",
                                   "The Sobol' indices rest on 7 of 16 base points (a base point counts when all "
                                   "its 4 runs succeeded); unreliable: fewer than 80 %."])
        self.assertTrue(row[4].endswith("; with the 3 failed runs counted either way: 0.09375 to 0.1875"), row[4])
        self.assertEqual(page.words("good"), [])
        self.assertTrue(page.words("alarm")[0].startswith("Unreliable: failed runs left 7 of 16 base points "
                                                          "complete (fewer than 80 %)"))

    def test_a_subset_simulation_page_does_not_give_level_0_as_the_answer(self):
        def build(f):
            saltelli_file(f)
            del f.attrs["design"]  # a file without it: its levels say subset simulation
            f["samples/level"] = np.repeat([0, 1, 2, 3], 4)
            for key, v in (("mean", 22.0), ("sem", 0.4), ("used", 4), ("failed", 0), ("not_finite", 0)):
                f[f"responses/y/{key}"] = v
            e = f.create_group("responses/y/exceedance")
            e["probability"], e["count"], e["successful"], e["failed"] = 0.0, 0, 4, 0
            e["interval"] = np.array([0.0, 0.49])
            r = f.create_group("rare_event/y")
            r["probability"], r["cov"], r["interval"] = 2.6e-6, 0.73, np.array([7.1e-7, 9.3e-6])
        write(self.path, build)
        with h5py.File(self.path) as f:
            row = response_row(f, f["samples/responses"], 0, "y", "N")
        self.assertEqual(row[4], "P(y > 25 N) = 2.6e-06: the subset simulation's, above (level 0 alone is not the "
                                 "answer)")
        self.assertNotIn("subset simulation", row[5])
        self.assertNotIn("no exceedance", " ".join(row))

    def region_file(self, f, runs=4, effective=None, near=(0.0, 0.0), with_group=True):
        saltelli_file(f)
        g = f.create_group("responses/y/exceedance/failure_region")
        f["responses/y/exceedance/failed"] = 2
        g.attrs["runs"] = runs
        if effective is not None:
            g.attrs["effective_runs"] = effective
        if runs == 0:
            return
        for key, v in (("mean_u", [1.9, -0.1]), ("mean_u2", [4.2, 1.1]), ("near_bound", near),
                       ("bound", [1.0, 2.0]), ("design_point", [0.99, 0.45]), ("importance", [0.9, 0.1])):
            g[key] = np.array(v)
            g[key].attrs["columns"] = ["a", "b"]
        g["unit_importance"] = np.array([0.9, 0.1]) if with_group else np.array([0.9])
        g["unit_importance"].attrs["columns"] = ["a", "b"] if with_group else ["both"]
        g.attrs["unit_inputs"] = ["a", "b"] if with_group else ["a, b"]

    def region_page(self, build):
        write(self.path, build)
        page = Collect()
        with h5py.File(self.path) as f:
            rows, counted = counted_rows(f)
            failure_region_section(f, page, rows, counted)
        return page

    def test_the_failure_region_table_and_its_rough_note(self):
        page = self.region_page(lambda f: self.region_file(f))
        header, rows = page.tables()[0]
        self.assertEqual(header, ["input or group", "importance", "mean u", "mean u²", "design point", "near a bound"])
        self.assertEqual(rows[0], ["a", "0.90", "1.90", "4.20", "0.99 kg", "0 % (bound 1 kg)"])
        self.assertIn("Rough: 4 runs beyond the limit for 2 inputs; chance alone moves each input's share (at least "
                      "20 would tell).", page.words("warning"))
        self.assertEqual(len(page.figures), 1)
        self.assertNotIn("P depends on where", " ".join(page.words()))
        grouped = self.region_page(lambda f: self.region_file(f, runs=40, effective=40.0, with_group=False))
        self.assertEqual(grouped.tables()[0][1], [["both", "0.90", "(2 inputs: per input in the file)", "", "", ""]])
        self.assertEqual(grouped.words("warning"), [])  # 40 runs for 2 inputs: not rough

    def test_chain_states_count_as_fewer_runs(self):
        page = self.region_page(lambda f: self.region_file(f, runs=30, effective=9.6))
        self.assertIn("Rough: 30 runs beyond the limit (as 10 independent ones: chain states) for 2 inputs; chance "
                      "alone moves each input's share (at least 20 would tell).", page.words("warning"))

    def test_a_bound_that_sets_p_is_warned_about(self):
        page = self.region_page(lambda f: self.region_file(f, runs=40, near=(0.95, 0.0)))
        self.assertIn("95 % of the failing runs have a within 1 % of its upper bound 1 kg: P depends on where that "
                      "distribution is cut off, not only on the dynamics.", page.words("warning"))

        def two_sided(f):
            self.region_file(f, runs=40, near=(0.95, 0.0))
            f["responses/y/exceedance/failure_region/mean_u"][0] = 0.05  # on both sides: |u| large, mean u ~ 0
        page = self.region_page(two_sided)
        self.assertIn("95 % of the failing runs have a within 1 % of the range of one of its bounds (most near 1 kg)",
                      " ".join(page.words("warning")))

    def test_no_failing_run_is_one_line_and_no_limit_is_nothing(self):
        page = self.region_page(lambda f: self.region_file(f, runs=0))
        self.assertEqual(page.words("paragraph")[-1], "y: no successful run exceeds the limit; 2 failed runs might "
                                                      "have.")
        self.assertEqual((page.tables(), page.figures), ([], []))

        def no_limit(f):
            saltelli_file(f, limit=np.nan)
            f.create_group("responses/y")
        page = self.region_page(no_limit)
        self.assertEqual(page.parts, [])

    def test_subset_simulation_uses_every_level_s_failure_region(self):
        def build(f):
            self.region_file(f, runs=0)  # level 0 alone: none beyond the limit
            f.attrs["design"] = "subset_simulation"
            f["samples/level"] = np.repeat([0, 1, 2, 3], 4)
            f["samples/responses"][12:, 0] = 30.0
            r = f.create_group("rare_event/y")
            r["failed_per_level"] = np.zeros(4)
            g = r.create_group("failure_region")
            g.attrs.update({"runs": 4, "unit_inputs": ["a", "b"]})
            for key, v in (("mean_u", [1.9, -0.1]), ("mean_u2", [4.2, 1.1]), ("near_bound", [0.0, 0.0]),
                           ("bound", [1.0, 2.0]), ("design_point", [0.99, 0.45])):
                g[key] = np.array(v)
                g[key].attrs["columns"] = ["a", "b"]
            g["unit_importance"] = np.array([0.3, 0.7])
            g["unit_importance"].attrs["columns"] = ["a", "b"]
        page = self.region_page(build)
        self.assertIn("y: the 4 runs beyond the limit, any level of the subset simulation.", page.words("paragraph"))
        self.assertEqual([row[0] for row in page.tables()[0][1]], ["b", "a"])
        self.assertNotIn("no successful run", " ".join(page.words()))
        self.assertIn("(level 0, the Monte-Carlo sample, 4 runs; grey, left axis)", page.figures[0][1])

    def test_every_run_of_the_extremes_table_is_inside_the_plots(self):
        def build(f):
            saltelli_file(f, big_ab=33.0)  # an AB run beyond every counted one
            sensitivity_group(f, "y", [0.2, 0.8], [[0.1, 0.3], [0.6, 1.1]], [1, 0], [1], [np.nan])
        write(self.path, build)
        page = Collect()
        with h5py.File(self.path) as f:
            rows, counted = counted_rows(f)
            scatter_figures(f, page, rows)
            response_figures(f, page, rows, counted)
        for ax in page.figures[0][0].axes[:2]:
            self.assertGreaterEqual(ax.get_ylim()[1], 33.0)
        self.assertIn("the 8 counted runs (dots) and the 8 AB runs (+", page.figures[0][1])
        self.assertGreaterEqual(page.figures[1][0].axes[0].get_xlim()[1], 33.0)
        self.assertIn("outlined, the 8 AB runs", page.figures[1][1])

    def test_subset_scatter_plots_are_coloured_by_level(self):
        def build(f):
            saltelli_file(f)
            f.attrs["design"] = "subset_simulation"
            f["samples/level"] = np.repeat([0, 1, 2, 3], 4)
            sensitivity_group(f, "y", [0.2, 0.8], [[0.1, 0.3], [0.6, 1.1]], [1, 0], [1], [np.nan])
        write(self.path, build)
        page = Collect()
        with h5py.File(self.path) as f:
            scatter_figures(f, page, counted_rows(f)[0])
        labels = [line.get_label() for line in page.figures[0][0].axes[0].get_lines()]
        self.assertEqual(labels[:4], ["level 0", "level 1", "level 2", "level 3"])
        self.assertIn("every run of every level (16), coloured by level", page.figures[0][1])

    def test_no_empty_srrc_map(self):
        def build(f):
            saltelli_file(f)
            sensitivity_group(f, "y", [0.2, 0.8], [[0.1, 0.3], [0.6, 1.1]], [1, 0], [1], [np.nan])
        write(self.path, build)
        page = Collect()
        with h5py.File(self.path, "a") as f:
            sensitivity_figures(f, page)
            f["sensitivity/y/srrc"][:] = [0.3, -0.5]
            sensitivity_figures(f, page)
        self.assertEqual(page.words("paragraph"), ["No SRRC map: the rank regression needs more runs than inputs (2 "
                                                   "inputs, 32 runs)."])
        self.assertEqual([len([a for a in fig.axes if a.get_title()]) for fig, _, _ in page.figures], [1, 2])

    def test_index_bars_stay_within_0_and_1(self):
        def build(f):
            saltelli_file(f)
            s = sensitivity_group(f, "y", [1.1, 0.3], [[0.8, 1.3], [-0.1, 0.5]], [0, 1], [1], [np.nan])
            c = s.create_group("sobol_convergence")
            c["base_points"], c["used"] = np.array([1.0, 2.0, 4.0]), np.array([1.0, 2.0, 4.0])
            for key in ("first_order", "total_order"):
                c[key] = np.full((3, 2), 0.5)
                c[key].attrs["columns"] = ["a", "b"]
                c[key + "_ci"] = np.tile([-0.2, 1.4], (3, 2, 1))
        write(self.path, build)
        page = Collect()
        with h5py.File(self.path) as f:
            index_figures(f, page)
        fig, caption, name = page.figures[0]
        bars = [p.get_width() for p in fig.axes[0].patches]
        self.assertEqual(len(bars), 4)
        self.assertTrue(all(0 <= w <= 1 for w in bars), bars)
        self.assertEqual(name, "sobol_indices_y")
        self.assertIn("from 16 of 16 base points", caption)
        self.assertEqual(fig.axes[1].get_ylim(), (0, 1.02))

    def test_the_extremes_table_gives_units_and_decodes_reasons(self):
        def build(f):
            saltelli_file(f)
            f["samples/status"][3] = 1
            f["samples/responses"][3, 0] = np.nan
            del f["samples/reason"]
            f.create_dataset("samples/reason", data=[""] * 3 + ["too_much_work at t = 1 s"] + [""] * 12,
                             dtype=h5py.string_dtype())
        write(self.path, build)
        page = Collect()
        with h5py.File(self.path) as f:
            self.assertIsInstance(f["samples/reason"][3], bytes)  # h5py 3: a string dataset reads as bytes
            extreme_samples(f, page, "e.h5")
        header, rows = page.tables()[0]
        self.assertEqual(header[2:5], ["value (with its unit) or reason", "a (kg)", "b (m)"])
        self.assertTrue(rows[0][2].endswith(" N"), rows[0])
        self.assertEqual(rows[-1][1:3], ["failed", "too_much_work at t = 1 s"])


def morris_file(f, trajectories=4):
    """A Morris screen over three factors: a (kg), b (m) and a list p[1..4] stepped together; one response y
    (N) with a limit. Blocks of U + 1 = 4 runs per trajectory; mu*, mu and sigma chosen by hand (b and p act
    nonlinearly: sigma >= mu*; p's sigma has no interval)."""
    inputs = ["a", "b"] + [f"p[{k}]" for k in range(1, 5)]
    n = 4 * trajectories
    f.attrs.update({"design": "morris", "morris_block": 4, "morris_levels": 4, "morris_trajectories": trajectories})
    f["samples/status"] = np.zeros(n, dtype=np.int32)
    x = np.random.default_rng(5).uniform(size=(n, 6))
    f["samples/inputs"] = x
    f["samples/inputs"].attrs.update({"columns": inputs, "column_units": ["kg", "m"] + ["rad"] * 4,
                                      "column_targets": ["a", "b"] + ["p"] * 4})
    r = f.create_dataset("samples/responses", data=(20 + 10 * x[:, 0])[:, None])
    r.attrs.update({"columns": ["y"], "column_units": ["N"], "limit": [25.0], "fail_if": ["above"]})
    f.create_dataset("samples/reason", data=[""] * n, dtype=h5py.string_dtype())
    s = f.create_group("sensitivity/y")
    factors = ["a", "b", "p"]
    for key, v, ci in (("mu_star", [10.0, 2.0, 0.5], [[9.0, 11.0], [0.5, 3.5], [0.2, 0.8]]),
                       ("mu", [10.0, -1.0, 0.1], [[9.0, 11.0], [-2.5, 0.5], [-0.3, 0.5]]),
                       ("sigma", [1.0, 3.0, 0.6], [[0.5, 1.5], [2.0, 4.0], [np.nan, np.nan]])):
        s[f"morris_{key}"] = np.array(v)
        s[f"morris_{key}"].attrs.update({"columns": factors, "units": "N"})
        s[f"morris_{key}_ci"] = np.array(ci)
        s[f"morris_{key}_ci"].attrs.update({"columns": ["low", "high"], "factors": factors})
    s["morris_effects"] = np.full(3, float(trajectories))
    s.attrs.update({"morris_units": factors, "morris_unit_inputs": ["a", "b", "p[1], p[2], p[3], p[4]"],
                    "morris_trajectories": trajectories, "morris_levels": 4, "rank_samples": trajectories,
                    "rank_r_squared": np.nan})
    s["spearman"], s["srrc"] = np.array([0.9, 0.3, 0.1, 0.1, 0.1, 0.1]), np.full(6, np.nan)
    s["spearman"].attrs["columns"] = inputs
    s["rank_measure_ci"] = np.tile([0.0, 1.0], (6, 1))
    for key, measure, order, told, needed in (("morris_ranking", "Morris mu*", [0, 1, 2], [1, 0], [np.nan, 30.0]),
                                              ("rank_ranking", "|Spearman|", range(6), [0] * 5, [np.nan] * 5)):
        g = s.create_group(key)
        g.attrs["measure"], g.attrs["resamples"] = measure, 1000
        g["order"], g["told_apart"], g["needed"] = np.array(list(order)), np.array(told), np.array(needed, float)
        g["difference_ci"] = np.zeros((len(told), 2))
    return s


class Morris(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.path = os.path.join(self.dir.name, "m.h5")

    def tearDown(self):
        self.dir.cleanup()

    def page_of(self, build):
        """The drivers section and the figures of a file built by `build`."""
        write(self.path, build)
        page = Collect()
        with h5py.File(self.path) as f:
            drivers_section(f, page, counted_rows(f)[0])
            index_figures(f, page)
            morris_figures(f, page)
        return page

    def test_each_trajectory_s_first_run_is_counted_and_said_to_be_a_screen(self):
        write(self.path, morris_file)
        with h5py.File(self.path) as f:
            rows, words = counted_rows(f)
            meaning = design_of(f).counted_runs_meaning(f)
        self.assertEqual(list(np.flatnonzero(rows)), [0, 4, 8, 12])
        self.assertTrue(words.startswith("the 4 independent runs of the 16 (each Morris trajectory's first run"), words)
        self.assertIn("each trajectory's first run (an independent draw, on the inputs' 4-level grid: a screen, not "
                      "an estimate of a small probability)", meaning)

    def test_the_ranking_is_by_mu_star_told_apart_as_the_bootstrap_says_and_not_clipped(self):
        write(self.path, morris_file)
        with h5py.File(self.path) as f:
            r = primary_ranking(f["sensitivity/y"], strings_of(f["samples/inputs"].attrs["columns"]))
        self.assertEqual((r.measure, r.word, r.share, list(r.order)), ("Morris mu*", "trajectories", False, [0, 1, 2]))
        self.assertEqual(r.members, [[0], [1], [2, 3, 4, 5]])
        page = self.page_of(morris_file)
        self.assertEqual(page.words("good"), ["y is driven by a 10 [9, 11] > b 2 [0.5, 3.5] ~ p 0.5 [0.2, 0.8] (Morris "
                                              "mu* [95 %], N per unit of u, from 4 trajectories). b and p cannot yet "
                                              "be told apart (about 30 trajectories would tell them apart)."])
        self.assertNotIn("matters little", page.words("good")[0])  # mu* is a size in N, not a share

    def test_the_table_gives_mu_star_mu_and_sigma_with_units_largest_mu_star_first(self):
        page = self.page_of(morris_file)
        header, rows = page.tables()[0]
        self.assertEqual(header, ["factor", "its inputs", "mu* [95 %] (N per unit of u)", "mu [95 %] (N per unit of u)",
                                  "sigma [95 %] (N per unit of u)", "elementary effects", "reading"])
        self.assertEqual([row[:6] for row in rows], [["a", "a", "10 [9, 11]", "10 [9, 11]", "1 [0.5, 1.5]", "4"],
                                                     ["b", "b", "2 [0.5, 3.5]", "-1 [-2.5, 0.5]", "3 [2, 4]", "4"],
                                                     ["p", "p[1..4]", "0.5 [0.2, 0.8]", "0.1 [-0.3, 0.5]", "0.6", "4"]])
        self.assertEqual(rows[0][6], "raises y")
        self.assertEqual(rows[1][6], "its effects change sign (|mu| < mu*): non-monotone; nonlinear or interacting "
                                     "(sigma >= mu*)")
        self.assertTrue(any(w.startswith("y: sigma >= mu*, nonlinear or interacting: b (sigma 3, mu* 2), p (sigma "
                                         "0.6, mu* 0.5).") for w in page.words("paragraph")))

    def test_the_figure_draws_mu_star_against_sigma_with_the_line_sigma_equals_mu_star(self):
        page = self.page_of(morris_file)
        self.assertEqual(len(page.figures), 1)
        fig, caption, name = page.figures[0]
        self.assertEqual(name, "morris_y")
        self.assertIn("dashed: sigma = mu*. Above the line a factor acts nonlinearly or through interactions", caption)
        self.assertIn("near the x-axis it acts linearly", caption)
        ax = fig.axes[0]
        self.assertEqual([t.get_text() for t in ax.texts], ["a", "b", "p"])
        dashed = [line for line in ax.get_lines() if line.get_linestyle() == "--"]
        self.assertEqual(len(dashed), 1)
        np.testing.assert_allclose(dashed[0].get_xdata(), dashed[0].get_ydata())
        self.assertEqual(ax.get_xlim()[0], 0)
        self.assertGreaterEqual(ax.get_xlim()[1], 11.0)  # every interval inside the axes
        self.assertGreaterEqual(ax.get_ylim()[1], 4.0)
        points = [line for line in ax.get_lines() if line.get_marker() == "o"][0]
        np.testing.assert_allclose(points.get_xdata(), [10.0, 2.0, 0.5])
        np.testing.assert_allclose(points.get_ydata(), [1.0, 3.0, 0.6])

    def test_no_morris_section_for_saltelli_or_monte_carlo(self):
        def saltelli(f):
            saltelli_file(f)
            sensitivity_group(f, "y", [0.2, 0.8], [[0.1, 0.3], [0.6, 1.1]], [1, 0], [1], [np.nan])

        def monte_carlo(f):
            saltelli(f)
            del f.attrs["design"], f["sensitivity/y/total_order"], f["sensitivity/y/total_order_ci"]
        for build in (saltelli, monte_carlo):
            page = self.page_of(build)
            self.assertNotIn("morris", " ".join(page.words()).lower())
            self.assertFalse([name for _, _, name in page.figures if name.startswith("morris")])
            with h5py.File(self.path) as f:
                self.assertNotIn("Morris", design_of(f).counted_runs_meaning(f) + counted_rows(f)[1])


def strings_of(v):
    return [x.decode() if isinstance(x, bytes) else str(x) for x in v]


if __name__ == "__main__":
    unittest.main()
