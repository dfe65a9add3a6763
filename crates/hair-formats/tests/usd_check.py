#!/usr/bin/env python3
"""Checks hairlod's USD text BasisCurves against Pixar's USD (usd-core), both ways.

`.ci/run` runs it after the tests (in a virtual environment with usd-core 26.11). By hand, from
the repository root:

    python3 -m venv /tmp/usdvenv && /tmp/usdvenv/bin/pip install usd-core==26.11   # once
    /tmp/usdvenv/bin/python crates/hair-formats/tests/usd_check.py

Set CARGO_TARGET_DIR as usual if you use one. The script

1. runs the ignored test `usd_check_write`, which writes `ours_single.usda` (one frame) and
   `ours_animated.usda` (three frames as `points.timeSamples`) with hairlod's writer, and the bits
   of every value written (`ours.json`);
2. opens both with `Usd.Stage.Open`, reads the BasisCurves' points at the default time and at
   time codes 0, 1, 2 (and 0.5, 7: interpolated and held), its counts, widths, colours and stage
   metadata, and compares them bit for bit with what was written;
3. writes BasisCurves files with the UsdGeom API (one Y-up in metres with time samples and
   vertex widths, one Z-up in centimetres with constant widths and two prims), lists what
   hairlod must read from them (converted to Y-up metres the way hairlod does: in double, then
   rounded to float) in `pixar.json`, and runs the ignored test `usd_check_read`, which reads
   them with `read_usda_file(_at)` and compares bit for bit; the same files exported as binary
   `.usdc` (read through the `openusd` crate at the default time), and a Z-up centimetre Mesh of
   a quad and a triangle as `.usda` and `.usdc` (read with `read_mesh_file`: points bit for bit,
   the quad as a fan of two triangles).

It prints one line per check and exits non-zero on the first difference.
"""

import json
import os
import struct
import subprocess
import sys
import tempfile

from pxr import Gf, Sdf, Usd, UsdGeom, Vt

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))


def bits(x):
    """The bits of x as a 32-bit float."""
    return struct.unpack("<I", struct.pack("<f", x))[0]


def f32(x):
    """x rounded to a 32-bit float."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def vec_bits(points):
    return [[bits(c) for c in p] for p in points]


def cargo_step(test, directory):
    env = dict(os.environ, HAIRLOD_USD_CHECK_DIR=directory)
    # `--workspace` as `.ci/run`'s `cargo test --workspace` builds it: `-p hair-formats` alone
    # unifies features differently and recompiles the crate and its dependencies (5 min on CI).
    command = ["cargo", "test", "-q", "--workspace", "--lib", "--", f"tests::usda::{test}",
               "--ignored", "--exact", "--nocapture"]
    result = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"FAIL: cargo step {test}:\n{result.stdout}\n{result.stderr}")
    for line in result.stdout.splitlines():
        if " points equal" in line:
            print("ok  hairlod read", line)


def check(condition, message):
    if not condition:
        sys.exit(f"FAIL: {message}")
    print("ok ", message)


def check_ours(directory):
    expected = json.load(open(os.path.join(directory, "ours.json")))
    counts = expected["counts"]
    for name, frames in [("ours_single.usda", [expected["single"]]),
                         ("ours_animated.usda", expected["frames"])]:
        path = os.path.join(directory, name)
        stage = Usd.Stage.Open(path)
        check(stage is not None, f"{name}: Usd.Stage.Open")
        check(UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y, f"{name}: upAxis Y")
        check(UsdGeom.GetStageMetersPerUnit(stage) == 1.0, f"{name}: metersPerUnit 1")
        curves = [UsdGeom.BasisCurves(p) for p in stage.Traverse() if p.IsA(UsdGeom.BasisCurves)]
        check(len(curves) == 1, f"{name}: one BasisCurves prim")
        c = curves[0]
        check(c.GetTypeAttr().Get() == "linear", f"{name}: type linear")
        check(list(c.GetCurveVertexCountsAttr().Get()) == counts, f"{name}: curveVertexCounts")
        widths = c.GetWidthsAttr().Get()
        check([bits(w) for w in widths] == expected["widths"], f"{name}: widths bit for bit")
        check(c.GetWidthsInterpolation() == UsdGeom.Tokens.vertex, f"{name}: widths vertex")
        colors = c.GetDisplayColorPrimvar()
        check(vec_bits(colors.Get()) == expected["colors"], f"{name}: displayColor bit for bit")
        check(colors.GetInterpolation() == UsdGeom.Tokens.vertex, f"{name}: displayColor vertex")
        points = c.GetPointsAttr()
        if len(frames) == 1:
            check(vec_bits(points.Get()) == frames[0], f"{name}: points bit for bit")
        else:
            check(stage.GetStartTimeCode() == 0 and stage.GetEndTimeCode() == len(frames) - 1,
                  f"{name}: start and end time codes")
            check(stage.GetTimeCodesPerSecond() == 30, f"{name}: timeCodesPerSecond 30")
            check(points.GetTimeSamples() == list(range(len(frames))), f"{name}: sample times")
            for t, frame in enumerate(frames):
                check(vec_bits(points.Get(t)) == frame, f"{name}: points at time {t} bit for bit")
            held = points.Get(7)
            check(vec_bits(held) == frames[-1], f"{name}: points held after the last sample")
            half = points.Get(0.5)
            first, second = frames[0], frames[1]
            unbits = lambda b: struct.unpack("<f", struct.pack("<I", b))[0]
            close = all(abs(half[i][k] - 0.5 * (unbits(first[i][k]) + unbits(second[i][k])))
                        <= 1e-6 * max(1.0, abs(half[i][k]))
                        for i in range(len(first)) for k in range(3))
            check(close, f"{name}: points at 0.5 interpolated")
            check(len(c.GetExtentAttr().GetTimeSamples()) == len(frames), f"{name}: extent samples")


def write_pixar(directory):
    cases = []
    # Y up, metres, animated, vertex widths, nested under an Xform.
    path = os.path.join(directory, "pixar_y_m.usda")
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    stage.SetStartTimeCode(1)
    stage.SetEndTimeCode(3)
    UsdGeom.Xform.Define(stage, "/groom")
    curves = UsdGeom.BasisCurves.Define(stage, "/groom/hair")
    curves.CreateTypeAttr(UsdGeom.Tokens.linear)
    counts = [3, 2, 4]
    curves.CreateCurveVertexCountsAttr(Vt.IntArray(counts))
    frames = {}
    for t in (1, 2, 3):
        pts = [Gf.Vec3f(0.1 * i + 0.01 * t, 0.7 / (i + 1), -0.333 * i * t) for i in range(9)]
        frames[t] = pts
        curves.GetPointsAttr().Set(Vt.Vec3fArray(pts), t)
    widths = [0.001 * (9 - i) for i in range(9)]
    curves.CreateWidthsAttr(Vt.FloatArray(widths))
    curves.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
    stage.GetRootLayer().Save()
    stage.GetRootLayer().Export(os.path.join(directory, "pixar_y_m.usdc"))
    offsets = [0, 3, 5, 9]
    widths_bits = [bits(w) for w in Vt.FloatArray(widths)]
    for t in (1, 2, 3):
        cases.append({"file": "pixar_y_m.usda", "time": t, "points": vec_bits(frames[t]),
                      "offsets": offsets, "widths": widths_bits})
    # The binary copy is read at the default time only (its earliest sample).
    for name in ("pixar_y_m.usda", "pixar_y_m.usdc"):
        cases.append({"file": name, "time": None, "points": vec_bits(frames[1]),
                      "offsets": offsets, "widths": widths_bits})

    # Z up, centimetres, two prims, constant widths.
    path = os.path.join(directory, "pixar_z_cm.usda")
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 0.01)
    all_points, all_widths, offsets = [], [], [0]
    for name, n, w in (("a", 3, 0.5), ("b", 4, 0.25)):
        c = UsdGeom.BasisCurves.Define(stage, f"/{name}")
        c.CreateTypeAttr(UsdGeom.Tokens.linear)
        c.CreateCurveVertexCountsAttr(Vt.IntArray([n]))
        pts = [Gf.Vec3f(1.5 * i, 2.25 + i, 10.0 * i + len(name)) for i in range(n)]
        c.CreatePointsAttr(Vt.Vec3fArray(pts))
        c.CreateWidthsAttr(Vt.FloatArray([w]))
        c.SetWidthsInterpolation(UsdGeom.Tokens.constant)
        # Y-up metres the way hairlod converts: scale in double, round to float, then (x, z, -y).
        for p in pts:
            x, y, z = (f32(v * 0.01) for v in p)
            all_points.append((x, z, -y))
            all_widths.append(f32(w * 0.01))
        offsets.append(offsets[-1] + n)
    stage.GetRootLayer().Save()
    stage.GetRootLayer().Export(os.path.join(directory, "pixar_z_cm.usdc"))
    for name in ("pixar_z_cm.usda", "pixar_z_cm.usdc"):
        cases.append({"file": name, "time": None, "points": vec_bits(all_points),
                      "offsets": offsets, "widths": [bits(w) for w in all_widths]})
    cases += write_pixar_mesh(directory)
    cases += write_pixar_many(directory)
    json.dump(cases, open(os.path.join(directory, "pixar.json"), "w"))
    print(f"ok  Pixar's USD wrote pixar_y_m, pixar_z_cm and pixar_mesh as .usda and .usdc "
          f"({len(cases)} reads to check)")


def write_pixar_many(directory):
    """Many curves as .usdc only, so that Pixar's crate writer compresses the arrays: the counts
    and integral widths as coded integers, the other widths as a look-up table."""
    path = os.path.join(directory, "pixar_many.usdc")
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    counts = [2 + i % 7 for i in range(300)]
    total = sum(counts)
    pts = [Gf.Vec3f(0.001 * i, 0.5 + 0.25 * (i % 3), -0.002 * i) for i in range(total)]
    points, offsets, widths = [], [0], []
    for name, w in (("lut", ([0.5, 0.25, 0.125][i % 3] for i in range(total))),
                    ("ints", (float(i % 5) for i in range(total)))):
        c = UsdGeom.BasisCurves.Define(stage, f"/{name}")
        c.CreateTypeAttr(UsdGeom.Tokens.linear)
        c.CreateCurveVertexCountsAttr(Vt.IntArray(counts))
        c.CreatePointsAttr(Vt.Vec3fArray(pts))
        w = list(w)
        c.CreateWidthsAttr(Vt.FloatArray(w))
        c.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
        points += pts
        widths += [bits(x) for x in Vt.FloatArray(w)]
        for n in counts:
            offsets.append(offsets[-1] + n)
    stage.GetRootLayer().Save()
    return [{"file": "pixar_many.usdc", "time": None, "points": vec_bits(points),
             "offsets": offsets, "widths": widths}]


def write_pixar_mesh(directory):
    """A Z-up, centimetre Mesh of a quad and a triangle, as .usda and .usdc: hairlod must read
    the points (converted as for curves) and the quad split into a fan from its first corner."""
    path = os.path.join(directory, "pixar_mesh.usda")
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 0.01)
    UsdGeom.Xform.Define(stage, "/body")
    mesh = UsdGeom.Mesh.Define(stage, "/body/head")
    pts = [Gf.Vec3f(0, 0, 0), Gf.Vec3f(10, 0, 0), Gf.Vec3f(10, 10, 0.5), Gf.Vec3f(0, 10, 0),
           Gf.Vec3f(20, 5, 1.25)]
    mesh.CreatePointsAttr(Vt.Vec3fArray(pts))
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray([4, 3]))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray([0, 1, 2, 3, 1, 4, 2]))
    stage.GetRootLayer().Save()
    stage.GetRootLayer().Export(os.path.join(directory, "pixar_mesh.usdc"))
    points = []
    for p in pts:
        x, y, z = (f32(v * 0.01) for v in p)
        points.append((x, z, -y))
    triangles = [[0, 1, 2], [0, 2, 3], [1, 4, 2]]
    return [{"file": name, "mesh": True, "points": vec_bits(points), "triangles": triangles}
            for name in ("pixar_mesh.usda", "pixar_mesh.usdc")]


def main():
    directory = tempfile.mkdtemp(prefix="hairlod-usd-check-")
    print("files in", directory, "with USD", Usd.GetVersion())
    cargo_step("usd_check_write", directory)
    check_ours(directory)
    write_pixar(directory)
    cargo_step("usd_check_read", directory)
    print("all checks passed")


if __name__ == "__main__":
    main()
