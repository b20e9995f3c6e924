#!/usr/bin/python3
"""Prints the time tools/render.py spends per stage on the given meshes (no assertions).

usage: bench_render.py [--size W,H] [--supersample S] MESH [MESH ...]
Figures: triangles, seconds (process CPU and wall) to read, for corner normals, to rasterize at
S times the size, and for the whole render() (normals, rasterization, shading, downsampling).
"""
import os
import sys
import time

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))

import render  # noqa: E402


def timed(function, *args, **kwargs):
    cpu, wall = time.process_time(), time.perf_counter()
    result = function(*args, **kwargs)
    return result, time.process_time() - cpu, time.perf_counter() - wall


def main(argv):
    width, height, supersample, paths = 800, 800, 2, []
    arguments = iter(argv)
    for argument in arguments:
        if argument == "--size":
            width, height = (int(x) for x in next(arguments).split(","))
        elif argument == "--supersample":
            supersample = int(next(arguments))
        else:
            paths.append(argument)
    if not paths:
        sys.exit(__doc__)
    print("%-28s %9s | %-13s | %-13s | %-13s | %-13s" % ("mesh", "triangles", "read cpu/wall", "normals",
                                                          "rasterize", "render"))
    for path in paths:
        mesh, read_cpu, read_wall = timed(render.read_mesh, path)
        camera = render.make_camera(mesh.positions, width, height)
        faces = render.face_normals(mesh.positions, mesh.triangles)
        _, normals_cpu, normals_wall = timed(render.corner_normals, mesh.positions, mesh.triangles, faces)
        big = camera.scaled(supersample)
        u, v, z = big.project(mesh.positions)
        _, raster_cpu, raster_wall = timed(render.rasterize, u, v, z, mesh.triangles, int(big.width), int(big.height))
        _, render_cpu, render_wall = timed(render.render, mesh.positions, mesh.triangles, camera,
                                           supersample=supersample)
        print("%-28s %9d | %5.2f / %5.2f | %5.2f / %5.2f | %5.2f / %5.2f | %5.2f / %5.2f  s at %dx%d, supersample %d"
              % (os.path.basename(path)[:28], len(mesh.triangles), read_cpu, read_wall, normals_cpu, normals_wall,
                 raster_cpu, raster_wall, render_cpu, render_wall, width, height, supersample))


if __name__ == "__main__":
    main(sys.argv[1:])
