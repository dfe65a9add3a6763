#!/usr/bin/env python3
"""Writes crates/hair-formats/tests/data/mesh_sequence.usda and mesh_sequence.usdc (the same
stage, text and binary) and mesh_sequence.json (its world-space points as Pixar's USD evaluates
them), the fixtures of the USD mesh sequence reader (src/tests/mesh_sequence.rs).

Needs Pixar's USD (`usd-core` on PyPI):

    python3 -m venv /tmp/usdvenv && /tmp/usdvenv/bin/pip install usd-core
    /tmp/usdvenv/bin/python crates/hair-formats/tests/make_usd_mesh_sequence_fixture.py

The stage: upAxis "Z", metersPerUnit 0.01 (centimetres), timeCodesPerSecond 24.

    /body         Xform, xformOpOrder [xformOp:translate, xformOp:rotateXYZ]
                    translate  {10: (0, 0, 0), 16: (60, 0, 0)}
                    rotateXYZ  {10: (0, 0, 0), 13: (0, 0, 45), 16: (30, 0, 90)}  degrees
    /body/skin    Mesh, a quad and a triangle (faceVertexCounts [4, 3], 5 points),
                    xformOpOrder [xformOp:translate:pivot, xformOp:orient, xformOp:scale,
                                  !invert!xformOp:translate:pivot]
                    translate:pivot (1, 0, 0), orient (w, x, y, z) = (cos 45°, sin 45°, 0, 0)
                    (90 degrees about X), scale (2, 1, 1), all constant
                    points {10: quad (0,0,0) (1,0,0) (1,1,0) (0,1,0) + (2,0,0),
                            12: the same with point 2 at (1,1,1),
                            14: the same with point 4 at (3,0,0)}
    /ground       Mesh, one triangle (0,0,0) (100,0,0) (0,100,0), no transform, no samples

mesh_topology_change.usdc (binary, no transforms) holds /blob, a Mesh whose faceVertexCounts and
faceVertexIndices are time-sampled, {1: [3], [0, 1, 2]} and {2: [4], [0, 1, 2, 3]} (a triangle,
then a quad, of 4 constant points): the reader refuses it, naming /blob and time code 2.

mesh_frames_per_second.usdc (binary) has framesPerSecond 12 and no timeCodesPerSecond, and one
Mesh, /tri, a triangle whose points are sampled at time codes 6 and 18: USD's rate falls back to
framesPerSecond, so the samples are at 0.5 s and 1.5 s.

Time codes of the sequence: the union of every sample that varies, 10, 12, 13, 14, 16, so
seconds 10/24, 12/24, 13/24, 14/24, 16/24. The JSON lists, for each time code, the world-space
points of /body/skin then /ground (namespace order) in stage units and axes (centimetres, Z up),
from `UsdGeom.Xformable.ComputeLocalToWorldTransform(t)` and `UsdGeom.Mesh.GetPointsAttr().Get(t)`.
"""

import json
import math
import os

from pxr import Gf, Sdf, Usd, UsdGeom, Vt

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
USDA = os.path.join(DATA, "mesh_sequence.usda")
USDC = os.path.join(DATA, "mesh_sequence.usdc")
JSON = os.path.join(DATA, "mesh_sequence.json")
TOPOLOGY = os.path.join(DATA, "mesh_topology_change.usdc")
RATE = os.path.join(DATA, "mesh_frames_per_second.usdc")

QUAD = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0)]
TIMES = [10.0, 12.0, 13.0, 14.0, 16.0]


def points_at(code):
    points = list(QUAD)
    if code >= 12:
        points[2] = (1, 1, 1)
    if code >= 14:
        points[4] = (3, 0, 0)
    return Vt.Vec3fArray([Gf.Vec3f(*p) for p in points])


def main():
    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 0.01)
    stage.SetTimeCodesPerSecond(24)
    stage.SetStartTimeCode(10)
    stage.SetEndTimeCode(16)

    body = UsdGeom.Xform.Define(stage, "/body")
    translate = body.AddTranslateOp()
    translate.Set(Gf.Vec3d(0, 0, 0), 10)
    translate.Set(Gf.Vec3d(60, 0, 0), 16)
    rotate = body.AddRotateXYZOp()
    rotate.Set(Gf.Vec3f(0, 0, 0), 10)
    rotate.Set(Gf.Vec3f(0, 0, 45), 13)
    rotate.Set(Gf.Vec3f(30, 0, 90), 16)

    skin = UsdGeom.Mesh.Define(stage, "/body/skin")
    skin.CreateFaceVertexCountsAttr([4, 3])
    skin.CreateFaceVertexIndicesAttr([0, 1, 2, 3, 1, 4, 2])
    for code in (10, 12, 14):
        skin.CreatePointsAttr().Set(points_at(code), code)
    pivot = skin.AddTranslateOp(opSuffix="pivot")
    pivot.Set(Gf.Vec3d(1, 0, 0))
    half = math.radians(45)
    skin.AddOrientOp().Set(Gf.Quatf(math.cos(half), math.sin(half), 0, 0))
    skin.AddScaleOp().Set(Gf.Vec3f(2, 1, 1))
    skin.AddTranslateOp(opSuffix="pivot", isInverseOp=True)

    ground = UsdGeom.Mesh.Define(stage, "/ground")
    ground.CreatePointsAttr([(0, 0, 0), (100, 0, 0), (0, 100, 0)])
    ground.CreateFaceVertexCountsAttr([3])
    ground.CreateFaceVertexIndicesAttr([0, 1, 2])

    stage.GetRootLayer().Export(USDA)
    stage.GetRootLayer().Export(USDC)

    # Evaluated by USD itself, from the written text file.
    stage = Usd.Stage.Open(USDA)
    samples = []
    for code in TIMES:
        time = Usd.TimeCode(code)
        points = []
        for path in ("/body/skin", "/ground"):
            mesh = UsdGeom.Mesh(stage.GetPrimAtPath(path))
            world = mesh.ComputeLocalToWorldTransform(time)
            for p in mesh.GetPointsAttr().Get(time):
                q = world.Transform(Gf.Vec3d(p))
                points.append([q[0], q[1], q[2]])
        samples.append({"time_code": code, "points": points})
        print(code, [[round(c, 6) for c in p] for p in points])
    with open(JSON, "w") as out:
        json.dump(
            {
                "time_codes_per_second": stage.GetTimeCodesPerSecond(),
                "meters_per_unit": UsdGeom.GetStageMetersPerUnit(stage),
                "up_axis": UsdGeom.GetStageUpAxis(stage),
                "samples": samples,
            },
            out,
            indent=1,
        )
    stage = Usd.Stage.CreateInMemory()
    blob = UsdGeom.Mesh.Define(stage, "/blob")
    blob.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])
    blob.CreateFaceVertexCountsAttr().Set([3], 1)
    blob.CreateFaceVertexCountsAttr().Set([4], 2)
    blob.CreateFaceVertexIndicesAttr().Set([0, 1, 2], 1)
    blob.CreateFaceVertexIndicesAttr().Set([0, 1, 2, 3], 2)
    stage.GetRootLayer().Export(TOPOLOGY)

    stage = Usd.Stage.CreateInMemory()
    stage.SetFramesPerSecond(12)
    tri = UsdGeom.Mesh.Define(stage, "/tri")
    tri.CreateFaceVertexCountsAttr([3])
    tri.CreateFaceVertexIndicesAttr([0, 1, 2])
    tri.CreatePointsAttr().Set([(0, 0, 0), (1, 0, 0), (0, 1, 0)], 6)
    tri.CreatePointsAttr().Set([(0, 0, 0), (2, 0, 0), (0, 1, 0)], 18)
    stage.GetRootLayer().Export(RATE)
    print("framesPerSecond", stage.GetFramesPerSecond(), "timeCodesPerSecond",
          stage.GetTimeCodesPerSecond())

    for path in (USDA, USDC, JSON, TOPOLOGY, RATE):
        print(path, os.path.getsize(path), "bytes")


if __name__ == "__main__":
    main()
