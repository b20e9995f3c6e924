"""Tests of tools/render.py, tools/plot_rd.py, tools/plot_sphere_function.py and tools/remesh_sweep.py: rasterizer coverage and depth, mesh readers,
camera framing, BD-rate on curves with known answers, rd.csv handling.

Run: /usr/bin/python3 -m unittest discover -s tests/tools -p 'test_plots.py'   (ctest: "tools: python plots")
"""
import contextlib
import csv
import io
import math
import os
import struct
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))

import numpy as np  # noqa: E402

import plot_rd  # noqa: E402
import plot_sphere_function  # noqa: E402
import remesh_sweep  # noqa: E402
import render  # noqa: E402


def screen_mesh(points):
    """u, v, z arrays from a list of (u, v, z)."""
    array = np.array(points, dtype=np.float64)
    return array[:, 0], array[:, 1], array[:, 2]


class RasterizerTest(unittest.TestCase):
    def test_single_triangle_covers_exactly_the_pixel_centres_inside(self):
        # Legs on u = 1 and v = 1, hypotenuse u + v = 8: centre (x + .5, y + .5) is inside when
        # x >= 1, y >= 1, x + y <= 7 (centres on the hypotenuse count as inside): 21 pixels.
        u, v, z = screen_mesh([(1, 1, 1), (7, 1, 1), (1, 7, 1)])
        front, inverse_z = render.rasterize(u, v, z, np.array([[0, 1, 2]]), 10, 10)
        expected = np.array([[x >= 1 and y >= 1 and x + y <= 7 for x in range(10)] for y in range(10)])
        np.testing.assert_array_equal(front >= 0, expected)
        self.assertEqual(int((front >= 0).sum()), 21)
        np.testing.assert_allclose(inverse_z[expected], 1.0)
        self.assertTrue((inverse_z[~expected] == 0).all())

    def test_clockwise_and_counter_clockwise_cover_the_same_pixels(self):
        u, v, z = screen_mesh([(1, 1, 1), (8, 1, 1), (1, 8, 1)])
        a, _ = render.rasterize(u, v, z, np.array([[0, 1, 2]]), 10, 10)
        b, _ = render.rasterize(u, v, z, np.array([[0, 2, 1]]), 10, 10)
        np.testing.assert_array_equal(a >= 0, b >= 0)

    def test_nearer_triangle_wins_in_either_order(self):
        # Two triangles with the same footprint, at depth 2 (index 0..2) and 1 (index 3..5).
        u, v, z = screen_mesh([(0, 0, 2), (10, 0, 2), (0, 10, 2), (0, 0, 1), (10, 0, 1), (0, 10, 1)])
        for triangles, near in ((np.array([[0, 1, 2], [3, 4, 5]]), 1), (np.array([[3, 4, 5], [0, 1, 2]]), 0)):
            front, inverse_z = render.rasterize(u, v, z, triangles, 10, 10)
            covered = front >= 0
            self.assertEqual(int(covered.sum()), 55)  # x + y <= 9
            self.assertTrue((front[covered] == near).all())
            np.testing.assert_allclose(inverse_z[covered], 1.0)

    def test_depth_is_perspective_correct_where_two_triangles_cross(self):
        # A: a square at z = 2. B: the same square with z = 1 on its left edge and z = 4 on its
        # right edge; 1/z is affine in screen space, 1/z_B(u) = 1 - 0.75 u / 20, which equals
        # 1/2 at u = 13.33: B is in front of A for pixel centres left of that, A to the right.
        u, v, z = screen_mesh([(0, 0, 2), (20, 0, 2), (20, 20, 2), (0, 20, 2),
                               (0, 0, 1), (20, 0, 4), (20, 20, 4), (0, 20, 1)])
        triangles = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
        front, inverse_z = render.rasterize(u, v, z, triangles, 20, 20)
        centres = np.arange(20) + 0.5
        b_in_front = 1 - 0.75 * centres / 20 > 0.5
        for row in range(20):
            np.testing.assert_array_equal(front[row] >= 2, b_in_front)
            np.testing.assert_allclose(inverse_z[row], np.maximum(1 - 0.75 * centres / 20, 0.5))

    def test_batches_of_any_size_give_the_same_image(self):
        rng = np.random.default_rng(7)
        u, v = rng.uniform(-5, 45, 60), rng.uniform(-5, 45, 60)
        z = rng.uniform(1, 3, 60)
        triangles = rng.integers(0, 60, (40, 3))
        whole, whole_z = render.rasterize(u, v, z, triangles, 40, 40)
        batched, batched_z = render.rasterize(u, v, z, triangles, 40, 40, fragment_budget=7)
        np.testing.assert_array_equal(whole, batched)
        np.testing.assert_array_equal(whole_z, batched_z)
        self.assertGreater(int((whole >= 0).sum()), 100)

    def test_triangles_behind_the_eye_or_off_screen_are_skipped(self):
        u, v, z = screen_mesh([(1, 1, -1), (8, 1, 1), (1, 8, 1), (-30, -30, 1), (-20, -30, 1), (-30, -20, 1)])
        front, _ = render.rasterize(u, v, z, np.array([[0, 1, 2], [3, 4, 5]]), 10, 10)
        self.assertTrue((front == -1).all())


def cube():
    positions = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=np.float64)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return (positions, *render.fan_triangles(quads))


class CameraTest(unittest.TestCase):
    def test_reference_fills_the_image_less_the_margin(self):
        positions, triangles, _ = cube()
        camera = render.make_camera(positions, 100, 80, 30, 20)
        image = render.render(positions, triangles, camera, supersample=1, transparent=True)
        rows, columns = np.nonzero(image[..., 3] > 0)
        # 5 % margin: the projection touches [5, 95] horizontally or [4, 76] vertically.
        self.assertTrue(rows.min() >= 3 and rows.max() <= 76 and columns.min() >= 4 and columns.max() <= 95)
        self.assertTrue((columns.min() <= 6 and columns.max() >= 93) or (rows.min() <= 5 and rows.max() >= 74))

    def test_a_series_framed_by_one_reference_keeps_its_scale(self):
        positions, triangles, _ = cube()
        camera = render.make_camera(positions, 64, 64, 0, 0)
        whole = render.render(positions, triangles, camera, supersample=1, transparent=True)[..., 3] > 0
        small = render.render(positions * 0.5 + 0.25, triangles, camera, supersample=1, transparent=True)[..., 3] > 0
        self.assertLess(small.sum(), 0.4 * whole.sum())  # a quarter of the area, give or take perspective
        self.assertGreater(small.sum(), 0.15 * whole.sum())

    def test_front_view_of_a_cube_shows_one_lit_face(self):
        positions, triangles, _ = cube()
        camera = render.make_camera(positions, 48, 48, 0, 0)
        image = render.render(positions, triangles, camera, flat=True, supersample=1)
        self.assertEqual(image.shape, (48, 48, 4))
        colours = image[..., :3].reshape(-1, 3)
        covered = (colours < 0.999).any(axis=1)
        # Flat face seen head-on: one colour (the specular term varies a little with the view ray).
        self.assertLess(np.ptp(colours[covered], axis=0).max(), 0.1)
        self.assertGreater(covered.sum(), 0.8 * 48 * 48)
        # Smooth normals keep edges sharper than the crease angle (40 degrees): a cube's faces meet
        # at 90, so smooth shading is flat shading; with a crease of 100 degrees it is not.
        smooth = render.render(positions, triangles, camera, supersample=1)
        np.testing.assert_allclose(smooth, image, atol=1e-12)
        rounded = render.render(positions, triangles, camera, supersample=1, crease_degrees=100)
        self.assertGreater(np.abs(rounded - image).max(), 0.1)

    def test_corner_normals_on_a_smooth_patch_are_the_angle_weighted_mean(self):
        # A fan of 4 triangles around vertex 0 on a shallow pyramid, all within the crease angle:
        # the apex corners get the angle-weighted mean of the four faces (by symmetry the axis);
        # rim vertex 2 is in faces 0 and 1 only, with equal angles there: their plain mean.
        positions = np.array([[0, 0, 0.2], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], dtype=np.float64)
        triangles = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]])
        faces = render.face_normals(positions, triangles)
        normals = render.corner_normals(positions, triangles, faces)
        np.testing.assert_allclose(normals[:, 0], np.tile([0, 0, 1.0], (4, 1)), atol=1e-12)
        faces /= np.linalg.norm(faces, axis=1, keepdims=True)
        expected = (faces[0] + faces[1]) / np.linalg.norm(faces[0] + faces[1])
        np.testing.assert_allclose(normals[0, 2], expected, atol=1e-12)
        np.testing.assert_allclose(normals[1, 1], expected, atol=1e-12)
        # A crease of 5 degrees separates the faces (16 degrees apart): each corner keeps its face's.
        sharp = render.corner_normals(positions, triangles, render.face_normals(positions, triangles), 5.0)
        np.testing.assert_allclose(sharp, np.repeat(faces[:, None, :], 3, axis=1), atol=1e-12)

    def test_corner_normals_match_the_pairwise_definition_on_a_rough_surface(self):
        # A height field with random bumps: some vertices on sharp edges, some not; the shortcut
        # (vertex normal where all faces are within half the crease) must equal the definition.
        rng = np.random.default_rng(3)
        grid = np.array([[x, y, 0.0] for y in range(7) for x in range(7)])
        grid[:, 2] = rng.uniform(0, 0.6, len(grid))
        triangles = np.array([t for y in range(6) for x in range(6) for t in
                              ([7 * y + x, 7 * y + x + 1, 7 * y + x + 8], [7 * y + x, 7 * y + x + 8, 7 * y + x + 7])])
        faces = render.face_normals(grid, triangles)
        unit = faces / np.linalg.norm(faces, axis=1, keepdims=True)
        corners = grid[triangles]
        angle = np.empty(triangles.shape)
        for i in range(3):
            a, b = corners[:, (i + 1) % 3] - corners[:, i], corners[:, (i + 2) % 3] - corners[:, i]
            angle[:, i] = np.arccos((a * b).sum(axis=1) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1))
        expected = np.zeros((len(triangles), 3, 3))
        for t in range(len(triangles)):
            for i in range(3):
                for f, j in zip(*np.nonzero(triangles == triangles[t, i])):
                    if unit[f] @ unit[t] >= math.cos(math.radians(25)):
                        expected[t, i] += angle[f, j] * unit[f]
        expected /= np.linalg.norm(expected, axis=2, keepdims=True)
        normals = render.corner_normals(grid, triangles, faces, 25.0)
        np.testing.assert_allclose(normals, expected, atol=1e-12)
        # Both kinds occur: corners whose normal is their face's own (every other face at the vertex
        # beyond the crease) and corners smoothed over several faces.
        own = np.isclose((normals * unit[:, None, :]).sum(axis=2), 1, rtol=0, atol=1e-12)
        self.assertTrue(own.any() and not own.all())

    def test_wireframe_draws_polygon_edges_only(self):
        positions, triangles, polygon_edges = cube()
        camera = render.make_camera(positions, 64, 64, 0, 0)
        plain = render.render(positions, triangles, camera, flat=True, supersample=1)
        edges = render.render(positions, triangles, camera, wire=True, flat=True, supersample=1,
                              polygon_edges=polygon_edges)
        every = render.render(positions, triangles, camera, wire=True, flat=True, supersample=1)
        diagonal = np.diag(np.arange(64))  # the front quad's diagonal runs corner to corner
        darker = lambda image: (image[..., :3].sum(axis=2) < plain[..., :3].sum(axis=2) - 0.3)
        self.assertGreater(darker(every)[diagonal > 0].sum() + darker(every)[np.fliplr(diagonal) > 0].sum(), 40)
        self.assertEqual(darker(edges)[10:54, 10:54].sum(), 0)  # no diagonal inside the face
        self.assertGreater(darker(edges).sum(), 100)  # the square's outline


class ReaderTest(unittest.TestCase):
    def setUp(self):
        self.directory = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.directory.cleanup()

    def write(self, name, content):
        path = os.path.join(self.directory.name, name)
        with open(path, "wb") as f:
            f.write(content if isinstance(content, bytes) else content.encode())
        return path

    # A square (two triangles after fanning the quad) and a triangle: 5 vertices.
    POSITIONS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 2]], dtype=np.float64)
    TRIANGLES = np.array([[0, 1, 2], [0, 2, 3], [0, 1, 4]])

    # The quad's diagonal (0, 2) is opposite corner 1 of (0, 1, 2) and corner 2 of (0, 2, 3).
    POLYGON_EDGES = np.array([[True, False, True], [True, True, False], [True, True, True]])

    def check(self, path):
        mesh = render.read_mesh(path)
        np.testing.assert_array_equal(mesh.positions, self.POSITIONS)
        np.testing.assert_array_equal(mesh.triangles, self.TRIANGLES)
        np.testing.assert_array_equal(mesh.polygon_edges, self.POLYGON_EDGES)

    def test_obj_with_slashes_negative_indices_and_a_quad(self):
        self.check(self.write("a.obj", "# comment\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
                                       "f 1//1 2//1 3//1 4//1\nv 0.5 0.5 2\nf -5/1 -4/2 -1/3\n"))

    def test_off_with_comments_counts_on_the_first_line_and_face_colours(self):
        self.check(self.write("a.off", "OFF 5 2 0\n# c\n0 0 0\n1 0 0\n1 1 0\n0 1 0 # x\n0.5 0.5 2\n"
                                       "4 0 1 2 3 255 0 0\n3 0 1 4\n"))

    def test_off_with_triangles_only(self):
        mesh = render.read_mesh(self.write("t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 2 1 0\n"))
        np.testing.assert_array_equal(mesh.triangles, [[2, 1, 0]])
        self.assertEqual(mesh.positions.shape, (3, 3))
        self.assertIsNone(mesh.colours)

    def ply_header(self, fmt, extra_vertex_property=True):
        return ("ply\nformat %s 1.0\ncomment test\nelement vertex 5\nproperty float x\nproperty float y\n"
                "property float z\n%selement face 2\nproperty list uchar int vertex_indices\nend_header\n"
                % (fmt, "property uchar red\n" if extra_vertex_property else ""))

    def test_ply_ascii(self):
        body = "".join("%g %g %g 7\n" % tuple(p) for p in self.POSITIONS) + "4 0 1 2 3\n3 0 1 4\n"
        self.check(self.write("a.ply", self.ply_header("ascii") + body))

    def binary_ply(self, order, faces):
        body = b"".join(struct.pack(order + "fffB", *p, 7) for p in self.POSITIONS)
        for face in faces:
            body += struct.pack(order + "B%di" % len(face), len(face), *face)
        fmt = "binary_little_endian" if order == "<" else "binary_big_endian"
        return self.ply_header(fmt).encode() + body

    def test_ply_vertex_colours_are_read_and_rendered(self):
        # uchar red, green, blue as meshlift decode writes them: a red, a green and a blue corner.
        header = ("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n")
        body = b"".join(struct.pack("<fffBBB", *p) for p in ((0, 0, 0, 255, 0, 0), (1, 0, 0, 0, 255, 0),
                                                             (0, 1, 0, 0, 0, 255)))
        mesh = render.read_mesh(self.write("c.ply", header.encode() + body + struct.pack("<B3i", 3, 0, 1, 2)))
        np.testing.assert_array_equal(mesh.colours, np.eye(3))
        camera = render.make_camera(mesh.positions, 60, 60, 0, 0)
        image = render.render(mesh.positions, mesh.triangles, camera, supersample=1, transparent=True, colours=mesh.colours)
        # Near each corner the pixels take that corner's colour; without colours they are grey-blue.
        covered = image[..., 3] > 0
        dominant = np.argmax(image[..., :3], axis=2)
        self.assertEqual(set(np.unique(dominant[covered])), {0, 1, 2})
        plain = render.render(mesh.positions, mesh.triangles, camera, supersample=1, transparent=True)
        self.assertTrue((np.argmax(plain[..., :3], axis=2)[covered] == 2).all())

    def test_ply_binary_both_byte_orders_mixed_face_sizes(self):
        self.check(self.write("le.ply", self.binary_ply("<", [(0, 1, 2, 3), (0, 1, 4)])))
        self.check(self.write("be.ply", self.binary_ply(">", [(0, 1, 2, 3), (0, 1, 4)])))

    def test_ply_binary_triangles_as_draco_writes_them(self):
        header = ("ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n")
        body = self.POSITIONS.astype("<f4").tobytes()
        body += b"".join(struct.pack("<B3i", 3, *t) for t in self.TRIANGLES)
        mesh = render.read_mesh(self.write("d.ply", header.encode() + body))
        np.testing.assert_array_equal(mesh.positions, self.POSITIONS)
        np.testing.assert_array_equal(mesh.triangles, self.TRIANGLES)
        self.assertTrue(mesh.polygon_edges.all())

    def test_ply_binary_quads_of_one_size_take_the_fixed_record_path(self):
        header = ("ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n")
        body = self.POSITIONS.astype("<f4").tobytes() + struct.pack("<B4iB4i", 4, 0, 1, 2, 3, 4, 1, 2, 3, 4)
        mesh = render.read_mesh(self.write("q.ply", header.encode() + body))
        # Fans grouped by position in the fan: first triangles of both quads, then the second ones.
        np.testing.assert_array_equal(mesh.triangles, [[0, 1, 2], [1, 2, 3], [0, 2, 3], [1, 3, 4]])
        np.testing.assert_array_equal(mesh.polygon_edges, [[True, False, True]] * 2 + [[True, True, False]] * 2)

    def test_bad_files_raise_with_the_reason(self):
        cases = {
            "empty.off": ("", "empty"),
            "range.off": ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "outside"),
            "short.off": ("OFF\n3 1 0\n0 0 0\n1 0 0\n", "exceed"),
            "cut.ply": (self.binary_ply("<", [(0, 1, 2, 3), (0, 1, 4)])[:-3], "cut short"),
            "nan.obj": ("v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "non-finite"),
            "a.stl": ("solid x\n", "extension"),
            "nothing.ply": ("ply\nformat ascii 1.0\nend_header\n", "no vertex element"),
            "points.ply": ("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                           "property float z\nend_header\n0 0 0\n", "no faces"),
        }
        for name, (content, reason) in cases.items():
            with self.subTest(name=name):
                with self.assertRaises(render.MeshReadError) as caught:
                    render.read_mesh(self.write(name, content))
                self.assertIn(reason, str(caught.exception))

    def test_missing_file_exits_with_code_3(self):
        with contextlib.redirect_stderr(io.StringIO()) as err:
            code = render.main([os.path.join(self.directory.name, "none.off"), "-o",
                                os.path.join(self.directory.name, "x.png")])
        self.assertEqual(code, render.EXIT_BAD_INPUT)
        self.assertIn("none.off", err.getvalue())


class StripTest(unittest.TestCase):
    def test_pick_orders_by_bytes_and_keeps_first_and_last(self):
        paths = ["d/prefix_%09d.ply" % b for b in (5000, 1000, 2000, 3000, 8000, 16000, 32000)]
        picked = render.pick_meshes(paths, 3)
        self.assertEqual([render.prefix_bytes(p) for p in picked], [1000, 5000, 32000])  # geometric: 1k, 5.7k, 32k
        self.assertEqual(len(render.pick_meshes(paths, 0)), 7)

    def test_strip_of_two_meshes_with_csv_captions(self):
        with tempfile.TemporaryDirectory() as directory:
            positions, triangles, _ = cube()
            paths = []
            for size, scale in ((500, 0.5), (1500, 1.0)):
                path = os.path.join(directory, "prefix_%09d.off" % size)
                with open(path, "w") as f:
                    f.write("OFF\n%d %d 0\n" % (len(positions), len(triangles)))
                    f.writelines("%g %g %g\n" % tuple(p * scale) for p in positions)
                    f.writelines("3 %d %d %d\n" % tuple(t) for t in triangles)
                paths.append(path)
            stream_csv = os.path.join(directory, "s.csv")
            with open(stream_csv, "w") as f:
                f.write("bytes,bits_per_vertex,vertices,bit_plane,psnr_db\n500,500,8,3,41.25\n1500,1500,8,0,inf\n")
            rows = render.read_stream_csv(stream_csv)
            self.assertEqual(render.caption(paths[0], positions, rows), "500 bytes\n500.00 bpv, 41.2 dB\n8 vertices")
            self.assertEqual(render.caption(paths[1], positions, rows), "1,500 bytes\n1500.00 bpv\n8 vertices")
            out = os.path.join(directory, "strip.png")
            self.assertEqual(render.main(["strip"] + paths + ["--csv", stream_csv, "--size", "60,50", "-o", out]), 0)
            import matplotlib.pyplot as plt
            image = plt.imread(out)
            self.assertEqual(image.shape[1], 120)
            self.assertGreater(image.shape[0], 50)


def power_curve(psnrs, scale=1.0):
    """log2 rate = (D - 40) / 6 + (D - 60)^3 / 3000: a cubic in D, so the fits are exact."""
    return [(scale * 2 ** ((d - 40) / 6 + (d - 60) ** 3 / 3000), d) for d in psnrs]


class BdRateTest(unittest.TestCase):
    def test_a_curve_shifted_by_a_factor_4_in_rate_gives_minus_75_percent(self):
        psnrs = [50, 54, 58, 62, 66, 70, 74, 78]
        draco = power_curve(psnrs, 4.0)
        meshlift = power_curve(psnrs)
        value, reason, details = plot_rd.bd_rate(draco, meshlift)
        self.assertEqual(reason, "")
        self.assertAlmostEqual(value, -0.75, places=9)
        self.assertEqual((details["low"], details["high"]), (55.0, 75.0))
        self.assertEqual((details["anchor_points"], details["test_points"]), (5, 5))
        self.assertAlmostEqual(plot_rd.bd_rate(meshlift, draco)[0], 3.0, places=9)

    def test_curves_sampled_at_different_psnrs_still_give_the_exact_shift(self):
        draco = power_curve([46, 52.5, 58.6, 64.7, 70.7, 76.7, 82.7], 4.0)
        meshlift = power_curve([40, 47, 53, 56, 61, 63, 69, 72, 74.5, 79])
        self.assertAlmostEqual(plot_rd.bd_rate(draco, meshlift)[0], -0.75, places=9)

    def test_a_rate_ratio_growing_with_psnr_gives_its_mean_log(self):
        # test = anchor * exp(k (D - 60)): mean log-ratio over [55, 75] is k (65 - 60).
        k = 0.05
        psnrs = np.linspace(50, 80, 13)
        anchor = [(2 ** (d / 10), d) for d in psnrs]
        test = [(r * math.exp(k * (d - 60)), d) for r, d in anchor]
        self.assertAlmostEqual(plot_rd.bd_rate(anchor, test)[0], math.exp(k * 5) - 1, places=9)

    def test_overlap_is_clipped_to_the_curves_and_the_interval(self):
        draco = power_curve([60, 63, 66, 69, 72], 2.0)
        meshlift = power_curve([50, 55, 60, 65, 70, 75, 80])
        value, reason, details = plot_rd.bd_rate(draco, meshlift, (55, 75))
        self.assertEqual((details["low"], details["high"]), (60, 72))
        self.assertAlmostEqual(value, -0.5, places=9)

    def test_too_little_overlap_is_not_a_number(self):
        draco = power_curve([40, 50, 56, 80])
        meshlift = power_curve([55, 60, 65, 70])
        value, reason, details = plot_rd.bd_rate(draco, meshlift, names=("Draco", "meshlift"))
        self.assertIsNone(value)
        self.assertIn("Draco has 1 point", reason)
        value, reason, _ = plot_rd.bd_rate(power_curve([30, 40, 50]), meshlift)
        self.assertIsNone(value)
        self.assertIn("no PSNR overlap", reason)


class RdCsvTest(unittest.TestCase):
    def write_rd(self, directory, rows):
        with open(os.path.join(directory, "rd.csv"), "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=plot_rd.COLUMNS)
            writer.writeheader()
            for row in rows:
                writer.writerow({c: row.get(c, "") for c in plot_rd.COLUMNS})

    def test_sweep_to_plots_and_table(self):
        rows = []
        for rate, psnr in power_curve([50, 55, 60, 65, 70, 75, 80]):
            rows.append(dict(mesh="m.off", codec="meshlift", scheme="loop", kind="prefix", bpv=rate, psnr_db=psnr))
        for qp, (rate, psnr) in enumerate(power_curve([48, 56, 64, 72, 80], 4.0), 8):
            rows.append(dict(mesh="m.off", codec="draco", kind="draco", param=qp, bpv=rate, psnr_db=psnr))
        rows.append(dict(mesh="bad.off", codec="meshlift", scheme="loop", kind="prefix", error="empty mesh"))
        with tempfile.TemporaryDirectory() as directory:
            self.write_rd(directory, rows)
            out = os.path.join(directory, "plots")
            with contextlib.redirect_stdout(io.StringIO()) as printed, contextlib.redirect_stderr(io.StringIO()) as err:
                self.assertEqual(plot_rd.main([directory, "-o", out]), 0)
            self.assertIn("bad.off", err.getvalue())
            self.assertIn("empty mesh", err.getvalue())
            self.assertIn("| m.off | loop | prefix | -75.0 % |", printed.getvalue())
            for name in ("rd.png", "rd.svg", "rd_m.png", "rd_m.svg", "bd_rate.md"):
                self.assertGreater(os.path.getsize(os.path.join(out, name)), 100, name)
            with open(os.path.join(out, "bd_rate.csv")) as f:
                table = list(csv.DictReader(f))
            self.assertEqual(len(table), 1)
            self.assertAlmostEqual(float(table[0]["bd_rate_percent"]), -75.0, places=3)

    def test_missing_columns_exit_with_code_3(self):
        with tempfile.TemporaryDirectory() as directory:
            with open(os.path.join(directory, "rd.csv"), "w") as f:
                f.write("mesh,bpv,psnr_db\nm,1,50\n")
            with contextlib.redirect_stderr(io.StringIO()) as err:
                self.assertEqual(plot_rd.main([directory]), plot_rd.EXIT_BAD_INPUT)
            self.assertIn("missing columns", err.getvalue())



class RemeshSweepTest(unittest.TestCase):
    @staticmethod
    def row(**fields):
        row = {"mesh": "m", "levels": 3, "density": "4", "input_vertices": 1000, "output_vertices": 4000,
               "ratio": "4.00", "base_vertices": 63, "psnr_db": "80.0", "flipped": "0", "degenerate": "0",
               "error": ""}
        row.update(fields)
        return row

    def test_targets_name_every_miss(self):
        self.assertEqual(remesh_sweep.targets_met(self.row()), "yes")
        self.assertEqual(remesh_sweep.targets_met(self.row(ratio="4.19")), "yes")  # within 5 % of 4x
        self.assertEqual(remesh_sweep.targets_met(self.row(psnr_db="74.9", ratio="4.30", flipped="2", degenerate="1")),
                         "no (74.9 < 75 dB, 4.30x > 4x, 3 folds)")
        self.assertEqual(remesh_sweep.targets_met(self.row(density="16", psnr_db="84.0")), "no (84.0 < 85 dB)")
        self.assertEqual(remesh_sweep.targets_met(self.row(flipped="1")), "no (1 folds)")
        self.assertEqual(remesh_sweep.targets_met(self.row(density="auto")), "")
        self.assertEqual(remesh_sweep.targets_met(self.row(density="2")), "")

    def test_off_vertex_count_reads_split_and_commented_headers(self):
        with tempfile.TemporaryDirectory() as directory:
            cases = {"a.off": "OFF 8 12 0\n", "b.off": "# c\nOFF\n# c\n7 3 0\n", "c.off": "PLY 8\n", "d.off": "OFF\n"}
            for name, text in cases.items():
                with open(os.path.join(directory, name), "w") as f:
                    f.write(text)
            counts = {name: remesh_sweep.off_vertex_count(os.path.join(directory, name)) for name in cases}
        self.assertEqual(counts, {"a.off": 8, "b.off": 7, "c.off": 0, "d.off": 0})
        self.assertEqual(remesh_sweep.off_vertex_count("/nonexistent.off"), 0)

if __name__ == "__main__":
    unittest.main()


class SphereFunctionPlotTest(unittest.TestCase):
    def write_dir(self, d, with_original=True):
        with open(os.path.join(d, "sphere_function.csv"), "w") as f:
            f.write("scheme,bytes,bits_per_sample,function_psnr_db,geometry_psnr_db\n")
            for scheme, base in (("linear", 20.0), ("butterfly", 21.0)):
                for k, size in enumerate((100, 200, 400)):
                    f.write(f"{scheme},{size},{size / 50:.3f},{base + 6 * k:.2f},50\n")
        image = np.arange(5 * 5 * 3, dtype=np.uint8).reshape(5, 5, 3)
        names = ["100", "200", "400"] + (["original"] if with_original else [])
        for name in names:
            with open(os.path.join(d, f"function_{name}.ppm"), "wb") as f:
                f.write(b"P6\n5 5\n255\n" + image.tobytes())

    def run_main(self, argv):
        old = sys.argv
        sys.argv = ["plot_sphere_function.py"] + argv
        try:
            with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
                return plot_sphere_function.main()
        finally:
            sys.argv = old

    def test_netpbm_reader_reads_what_the_bench_writes(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "a.pgm")
            with open(path, "wb") as f:
                f.write(b"P5\n3 2\n255\n" + bytes([0, 51, 255, 102, 153, 204]))
            image = plot_sphere_function.read_netpbm(path)
            self.assertEqual(image.shape, (2, 3))
            self.assertAlmostEqual(image[0, 1], 0.2)
            self.assertAlmostEqual(image[1, 2], 0.8)

    def test_curve_and_strip_are_written(self):
        with tempfile.TemporaryDirectory() as d:
            self.write_dir(d)
            self.assertEqual(self.run_main([d]), 0)
            for name in ("sphere_function_rd.png", "sphere_function_rd.svg", "sphere_function_strip.png"):
                self.assertGreater(os.path.getsize(os.path.join(d, name)), 1000, name)

    def test_missing_original_exits_with_code_3(self):
        with tempfile.TemporaryDirectory() as d:
            self.write_dir(d, with_original=False)
            self.assertEqual(self.run_main([d]), 3)
