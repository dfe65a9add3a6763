#!/usr/bin/env python3
"""Checks that a deforming character from a DCC tool runs through `hairlod render` (issue 53).

Done-when of issue 53: a USD character whose head mesh is time-sampled (48 frames at 24 time
codes per second, a nod plus a squash and stretch) with a BasisCurves groom on it, as a DCC tool
writes one, runs through `hairlod render` with automatic levels; every exported root lies within
0.5 mm of its frame-0 barycentric point on the deformed mesh at every time sample; Pixar's USD
opens the export with the body's time codes. The same for an Alembic mesh sequence.

CI runs it as `"$venv/bin/python" .ci/character_check.py target/debug/hairlod` in a virtual
environment with usd-core 26.11 and alembic3d 1.8.12.1 (plain Python otherwise: no numpy). By
hand, from the repository root, after a build (`cargo build -p hair-cli`):

    python3 -m venv /tmp/charvenv
    /tmp/charvenv/bin/pip install usd-core==26.11 alembic3d==1.8.12.1          # once
    /tmp/charvenv/bin/python .ci/character_check.py target/debug/hairlod

About 1.5 minutes with the debug binary on 2 cores (each render about 25 s). `--keep DIR` writes
everything into DIR (created) and leaves it there, otherwise a temporary folder is used and
removed; `--only usd` or `--only abc` runs one character. In that folder the script

1. writes `usd/character.usda` with Pixar's UsdGeom API, as a DCC tool writes a character:
   `upAxis = "Z"`, `metersPerUnit = 0.01`, 24 time codes per second, codes 1..48.
   `/character` is an Xform that nods (`xformOp:translate`, `xformOp:translate:pivot`,
   time-sampled `xformOp:rotateX`, `!invert!xformOp:translate:pivot`: 10° · sin(π (t − t1))
   about the neck); `/character/head` a closed UV sphere of quads and pole triangles (radius
   10 cm, centred 12 cm above the neck), counter-clockwise seen from outside, whose `points` are
   time-sampled at codes 1..48 with a squash and stretch about the neck that keeps the volume
   (z · s, x and y / √s, s = 1 + 0.06 sin(2π (t − t1)), t = code / 24 s); `/groom` a linear
   BasisCurves at the root with vertex widths, in the rest pose of code 1, every curve rooted on
   a triangle of the code-1 mesh (world positions) over the upper part of the head.
   Beside it `character.toml` (groom and body from that file, `[lod] mode = "auto"`, 48 frames at
   24 fps, `[output] usd = true`), and runs `hairlod render character.toml --out out` (timed);
2. opens `out/hair.usda` with `Usd.Stage.Open` and checks: Y up, metres, 24 time codes per
   second from code 1 to 48; `/hair` (BasisCurves) and `/body` (Mesh, triangles) have time
   samples at exactly codes 1..48; `/body`'s points at every code equal the input head's world
   points at that code (`ComputeLocalToWorldTransform(code)` × points(code), read back through
   Pixar's USD, then converted as hairlod converts a Z-up centimetre stage: × metersPerUnit,
   (x, y, z) → (x, z, −y)) within 1e-5 m, vertex for vertex, its triangles cut from the input's
   polygons and facing outwards; the roots (every curve's first point): at code 1 each root's
   closest point on the exported body, its triangle, barycentric coordinates and the root's offset
   in the triangle's frame (first edge, in-plane perpendicular, normal); at every code the root
   must lie within 0.5 mm of that barycentric point plus the offset turned with the triangle's
   frame; and the roots must move (by more than 5 mm), so the check is not vacuous;
3. the same for `abc/character.abc`, written with Alembic's Python bindings (Ogawa): the same
   head in Y-up metres, a PolyMesh (clockwise faces, as Alembic stores them) under an Xform with
   the nod (translate, translate pivot, rotateX, translate −pivot), 48 samples of a uniform time
   sampling from 1/24 s, 1/24 s apart, and the groom in `groom.usda` (Y up, metres, rooted on the
   first sample's mesh). Alembic has no time codes: the export's are the scene's fps (24) and the
   body's first sample time (1/24 s), so codes 1..48 again. The reference body is read back with
   Alembic's own reader (`IXform` matrices × `IPolyMesh` positions).

The reference is what Pixar's USD and Alembic's library read from the files this script wrote,
never hairlod's own readers. It prints one line per check (`ok: …` / `FAIL: …`) and exits
non-zero on the first failure.
"""

import argparse
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time

from pxr import Gf, Usd, UsdGeom, Vt

# The character, in the USD file's units (centimetres, +Z up), mesh-local (the neck at 0).
RADIUS = 10.0
CENTRE = (0.0, 0.0, 12.0)
RINGS = 24  # latitude bands: 2 · 40 pole triangles + 22 · 40 quads = 1,840 triangles
SEGMENTS = 40
PLACE = (0.0, 1.0, -1.0)  # /character's static xformOp:translate
PIVOT = (0.0, 0.0, 1.0)  # the nod's pivot (xformOp:translate:pivot)
NOD_DEGREES = 10.0
SQUASH = 0.06
FRAMES = 48
CODES_PER_SECOND = 24.0
FIRST_CODE = 1
CODES = list(range(FIRST_CODE, FIRST_CODE + FRAMES))
CURVES = 900
CURVE_POINTS = 12
CURVE_LENGTH = 12.0
ROOT_WIDTH, TIP_WIDTH = 0.008, 0.004  # 80 and 40 µm
METERS_PER_UNIT = 0.01

ROOT_TOLERANCE = 0.5e-3  # m
BODY_TOLERANCE = 1e-5  # m
MIN_ROOT_TRAVEL = 5e-3  # m


def check(condition, message):
    if not condition:
        print(f"FAIL: {message}", flush=True)
        sys.exit(1)
    print(f"ok: {message}", flush=True)


# Small vector helpers (plain Python: the CI venv has no numpy).
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    return mul(a, 1.0 / norm(a))


def seconds(code):
    return code / CODES_PER_SECOND


def nod_degrees(code):
    return NOD_DEGREES * math.sin(2.0 * math.pi * 0.5 * (seconds(code) - seconds(FIRST_CODE)))


def squash(code):
    return 1.0 + SQUASH * math.sin(2.0 * math.pi * 1.0 * (seconds(code) - seconds(FIRST_CODE)))


def rest_head():
    """The head's rest points (mesh-local, cm, Z up) and faces (counter-clockwise from outside)."""
    points = [add(CENTRE, (0.0, 0.0, RADIUS))]
    for i in range(1, RINGS):
        theta = math.pi * i / RINGS
        for j in range(SEGMENTS):
            phi = 2.0 * math.pi * j / SEGMENTS
            d = (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta))
            points.append(add(CENTRE, mul(d, RADIUS)))
    points.append(add(CENTRE, (0.0, 0.0, -RADIUS)))
    bottom = len(points) - 1

    def ring(i, j):  # ring i in 1..RINGS-1
        return 1 + (i - 1) * SEGMENTS + j % SEGMENTS

    faces = []
    for j in range(SEGMENTS):
        faces.append([0, ring(1, j), ring(1, j + 1)])
    for i in range(1, RINGS - 1):
        for j in range(SEGMENTS):
            faces.append([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)])
    for j in range(SEGMENTS):
        faces.append([bottom, ring(RINGS - 1, j + 1), ring(RINGS - 1, j)])
    for f in faces:  # every polygon faces outwards
        a, b, c = (points[k] for k in f[:3])
        assert dot(cross(sub(b, a), sub(c, a)), sub(a, CENTRE)) > 0.0
    return points, faces


def squashed(points, code):
    """The head at `code`: squashed and stretched about the neck (mesh-local 0), volume kept."""
    s = squash(code)
    across = 1.0 / math.sqrt(s)
    return [(p[0] * across, p[1] * across, p[2] * s) for p in points]


def triangles_of(faces):
    """Fan triangulation of polygons (as hairlod's readers cut them): (polygon, triangle) pairs."""
    out = []
    for k, f in enumerate(faces):
        for i in range(1, len(f) - 1):
            out.append((k, (f[0], f[i], f[i + 1])))
    return out


def make_groom(world, faces):
    """Curves rooted on triangles of the world rest mesh `world` (cm, Z up) over the upper part
    of the head, growing outwards and falling a little: lists of points (cm, Z up)."""
    rng = random.Random(53)
    centre = add(CENTRE, PLACE)
    tris = []
    areas = []
    for _, (a, b, c) in triangles_of(faces):
        pa, pb, pc = world[a], world[b], world[c]
        middle = mul(add(add(pa, pb), pc), 1.0 / 3.0)
        if middle[2] - centre[2] > 0.15 * RADIUS:
            tris.append((pa, pb, pc))
            areas.append(0.5 * norm(cross(sub(pb, pa), sub(pc, pa))))
    cumulative = []
    total = 0.0
    for a in areas:
        total += a
        cumulative.append(total)
    curves = []
    segment = CURVE_LENGTH / (CURVE_POINTS - 1)
    down = (0.0, 0.0, -1.0)
    for _ in range(CURVES):
        x = rng.random() * total
        k = next(i for i, c in enumerate(cumulative) if c >= x)
        pa, pb, pc = tris[k]
        r1, r2 = math.sqrt(rng.random()), rng.random()
        u, v, w = 1.0 - r1, r1 * (1.0 - r2), r1 * r2
        root = add(add(mul(pa, u), mul(pb, v)), mul(pc, w))
        n = unit(sub(root, centre))
        side = (n[0], n[1], 0.0)
        side = unit(side) if norm(side) > 1e-6 else (1.0, 0.0, 0.0)
        fall = unit(add(mul(side, 0.6), mul(down, 0.8)))
        curve = [root]
        for i in range(1, CURVE_POINTS):
            blend = 0.75 * i / (CURVE_POINTS - 1)
            direction = unit(add(mul(n, 1.0 - blend), mul(fall, blend)))
            curve.append(add(curve[-1], mul(direction, segment)))
        curves.append(curve)
    return curves


def write_curves(stage, path, curves):
    prim = UsdGeom.BasisCurves.Define(stage, path)
    prim.CreateTypeAttr(UsdGeom.Tokens.linear)
    prim.CreateCurveVertexCountsAttr(Vt.IntArray([len(c) for c in curves]))
    prim.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(*p) for c in curves for p in c]))
    widths = []
    for c in curves:
        for i in range(len(c)):
            widths.append(ROOT_WIDTH + (TIP_WIDTH - ROOT_WIDTH) * i / (len(c) - 1))
    return prim, widths


def write_usd_character(folder):
    """character.usda (Z up, cm, codes 1..48) and the world head points hairlod must export."""
    path = os.path.join(folder, "character.usda")
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, METERS_PER_UNIT)
    stage.SetTimeCodesPerSecond(CODES_PER_SECOND)
    stage.SetFramesPerSecond(CODES_PER_SECOND)
    stage.SetStartTimeCode(CODES[0])
    stage.SetEndTimeCode(CODES[-1])

    character = UsdGeom.Xform.Define(stage, "/character")
    stage.SetDefaultPrim(character.GetPrim())
    character.AddTranslateOp().Set(Gf.Vec3d(*PLACE))
    pivot = character.AddTranslateOp(opSuffix="pivot")
    pivot.Set(Gf.Vec3d(*PIVOT))
    nod = character.AddRotateXOp()
    character.AddTranslateOp(opSuffix="pivot", isInverseOp=True)
    for code in CODES:
        nod.Set(nod_degrees(code), code)

    points, faces = rest_head()
    head = UsdGeom.Mesh.Define(stage, "/character/head")
    head.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    head.CreateOrientationAttr(UsdGeom.Tokens.rightHanded)
    head.CreateFaceVertexCountsAttr(Vt.IntArray([len(f) for f in faces]))
    head.CreateFaceVertexIndicesAttr(Vt.IntArray([k for f in faces for k in f]))
    head_points = head.CreatePointsAttr()
    extent = head.CreateExtentAttr()
    for code in CODES:
        frame = Vt.Vec3fArray([Gf.Vec3f(*p) for p in squashed(points, code)])
        head_points.Set(frame, code)
        extent.Set(UsdGeom.PointBased.ComputeExtent(frame), code)

    # The groom in the rest pose: on the code-1 mesh in world coordinates, read back through USD.
    first = world_points_usd(head, CODES[0])
    curves = make_groom(first, faces)
    groom, widths = write_curves(stage, "/groom", curves)
    groom.CreateWidthsAttr(Vt.FloatArray(widths))
    groom.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
    stage.GetRootLayer().Save()

    reference = {}
    for code in CODES:
        reference[code] = [z_up_cm_to_hairlod(p) for p in world_points_usd(head, code)]
    return path, faces, reference, len(curves)


def world_points_usd(mesh, code):
    """A USD mesh's points at `code` in world coordinates (file units), as Pixar's USD composes."""
    matrix = UsdGeom.Xformable(mesh.GetPrim()).ComputeLocalToWorldTransform(code)
    points = mesh.GetPointsAttr().Get(code)
    return [tuple(matrix.Transform(Gf.Vec3d(p))) for p in points]


def z_up_cm_to_hairlod(p):
    """hairlod's conversion of a Z-up, 0.01-metres-per-unit stage: scale, then (x, z, −y)."""
    x, y, z = (c * METERS_PER_UNIT for c in p)
    return (x, z, -y)


def write_scene(folder, groom, body):
    text = f"""# Written by .ci/character_check.py.
version = 2

[groom]
file = "{groom}"

[body]
file = "{body}"

[lod]
mode = "auto"

[frames]
count = {FRAMES}
fps = {CODES_PER_SECOND:g}
size = "160x90"

[output]
usd = true
"""
    path = os.path.join(folder, "character.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def render(binary, scene, out):
    command = [binary, "render", scene, "--out", out]
    print("running", " ".join(command), flush=True)
    start = time.monotonic()
    result = subprocess.run(command, capture_output=True, text=True)
    elapsed = time.monotonic() - start
    if result.returncode != 0:
        print(result.stdout[-4000:])
        print(result.stderr[-4000:])
    check(result.returncode == 0, f"hairlod render {os.path.basename(os.path.dirname(scene))} "
          f"(exit {result.returncode}, {elapsed:.1f} s)")
    print(f"  render took {elapsed:.1f} s", flush=True)
    return elapsed


# The Alembic character: the same head in Y-up metres.
def y_up_m(p):
    """A point of the Z-up centimetre character in Y-up metres (hairlod's conversion)."""
    return z_up_cm_to_hairlod(p)


def write_abc_character(folder):
    import imath
    from alembic3d import Abc, AbcCoreAbstract, AbcGeom

    def v3f_array(points):
        array = imath.V3fArray(len(points))
        for i, p in enumerate(points):
            array[i] = imath.V3f(*p)
        return array

    def int_array(values):
        array = imath.IntArray(len(values))
        for i, v in enumerate(values):
            array[i] = v
        return array

    path = os.path.join(folder, "character.abc")
    points, faces = rest_head()
    # Alembic stores faces clockwise seen from their front.
    abc_faces = [list(reversed(f)) for f in faces]
    archive = Abc.OArchive(path)  # Ogawa, the default
    sampling = AbcCoreAbstract.TimeSampling(1.0 / CODES_PER_SECOND, seconds(CODES[0]))
    index = archive.addTimeSampling(sampling)
    character = AbcGeom.OXform(archive.getTop(), "character", index)
    head = AbcGeom.OPolyMesh(character, "head", index)
    place, pivot = y_up_m(PLACE), y_up_m(PIVOT)
    kTranslate = AbcGeom.XformOperationType.kTranslateOperation
    kRotateX = AbcGeom.XformOperationType.kRotateXOperation
    for code in CODES:
        sample = AbcGeom.XformSample()
        ops = [(kTranslate, place), (kTranslate, pivot), (kRotateX, None),
               (kTranslate, mul(pivot, -1.0))]
        for kind, value in ops:
            op = AbcGeom.XformOp(kind, 0)
            if value is None:
                # A rotation about X is the same angle after Z-up → Y-up (itself a turn about X).
                op.setChannelValue(0, nod_degrees(code))
            else:
                for c in range(3):
                    op.setChannelValue(c, value[c])
            sample.addOp(op)
        character.getSchema().set(sample)
        frame = [y_up_m(p) for p in squashed(points, code)]
        head.getSchema().set(AbcGeom.OPolyMeshSchemaSample(
            v3f_array(frame), int_array([k for f in abc_faces for k in f]),
            int_array([len(f) for f in abc_faces])))
    del head, character, archive

    reference = read_abc_world(path)
    times = sorted(reference)
    check(len(times) == FRAMES and all(abs(a - seconds(c)) < 1e-9 for a, c in zip(times, CODES)),
          f"alembic3d reads {len(times)} samples at {times[0]:.6g} .. {times[-1]:.6g} s "
          f"(want {FRAMES} at 1/24 .. 2 s)")
    by_code = {c: reference[t] for c, t in zip(CODES, sorted(reference))}

    # The groom: on the first sample's world mesh, Y up, metres (as the body).
    groom_path = os.path.join(folder, "groom.usda")
    stage = Usd.Stage.CreateNew(groom_path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    # make_groom works in the Z-up centimetre frame: take the first sample back there.
    first_cm = [(p[0] / METERS_PER_UNIT, -p[2] / METERS_PER_UNIT, p[1] / METERS_PER_UNIT)
                for p in by_code[CODES[0]]]
    curves = [[y_up_m(p) for p in c] for c in make_groom(first_cm, faces)]
    groom, widths = write_curves(stage, "/groom", curves)
    groom.CreateWidthsAttr(Vt.FloatArray([w * METERS_PER_UNIT for w in widths]))
    groom.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
    stage.SetDefaultPrim(groom.GetPrim())
    stage.GetRootLayer().Save()
    return path, groom_path, faces, by_code, len(curves)


def read_abc_world(path):
    """{time [s]: world points [m]} of every sample of the archive's one PolyMesh, as Alembic's
    own reader composes its parents' transforms (row vectors: p · M)."""
    import imath
    from alembic3d import Abc, AbcGeom

    archive = Abc.IArchive(path)
    meshes = []

    def walk(obj, parents):
        for i in range(obj.getNumChildren()):
            child = obj.getChild(i)
            header = child.getHeader()
            if AbcGeom.IXform.matches(header):
                walk(child, parents + [AbcGeom.IXform(child, Abc.WrapExistingFlag.kWrapExisting)])
            elif AbcGeom.IPolyMesh.matches(header):
                meshes.append((AbcGeom.IPolyMesh(child, Abc.WrapExistingFlag.kWrapExisting),
                               parents))
            else:
                walk(child, parents)

    walk(archive.getTop(), [])
    check(len(meshes) == 1, "alembic3d finds one PolyMesh")
    mesh, parents = meshes[0]
    schema = mesh.getSchema()
    sampling = schema.getTimeSampling()
    out = {}
    for i in range(schema.getNumSamples()):
        t = sampling.getSampleTime(i)
        selector = Abc.ISampleSelector(t)
        matrix = imath.M44d()
        matrix.makeIdentity()
        for xform in parents:  # outermost first: world = local · M_inner · … · M_outer
            matrix = xform.getSchema().getValue(selector).getMatrix() * matrix
        points = schema.getValue(selector).getPositions()
        world = []
        for p in points:
            q = imath.V3d(p[0], p[1], p[2]) * matrix
            world.append((q[0], q[1], q[2]))
        out[t] = world
    return out


# The export check.
def closest_on_triangle(p, a, b, c):
    """The closest point to p on triangle abc and its barycentric coordinates (Ericson 5.1.5)."""
    ab, ac, ap = sub(b, a), sub(c, a), sub(p, a)
    d1, d2 = dot(ab, ap), dot(ac, ap)
    if d1 <= 0 and d2 <= 0:
        return a, (1.0, 0.0, 0.0)
    bp = sub(p, b)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    if d3 >= 0 and d4 <= d3:
        return b, (0.0, 1.0, 0.0)
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        v = d1 / (d1 - d3)
        return add(a, mul(ab, v)), (1.0 - v, v, 0.0)
    cp = sub(p, c)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    if d6 >= 0 and d5 <= d6:
        return c, (0.0, 0.0, 1.0)
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        w = d2 / (d2 - d6)
        return add(a, mul(ac, w)), (1.0 - w, 0.0, w)
    va = d3 * d6 - d5 * d4
    if va <= 0 and (d4 - d3) >= 0 and (d5 - d6) >= 0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return add(b, mul(sub(c, b), w)), (0.0, 1.0 - w, w)
    denom = 1.0 / (va + vb + vc)
    v, w = vb * denom, vc * denom
    return add(a, add(mul(ab, v), mul(ac, w))), (1.0 - v - w, v, w)


def frame_of(a, b, c):
    """The triangle's frame: first edge normalised, the in-plane perpendicular, the normal."""
    e1 = unit(sub(b, a))
    n = unit(cross(sub(b, a), sub(c, a)))
    return e1, cross(n, e1), n


def bind_roots(roots, points, triangles):
    """Each root's triangle, barycentric coordinates and offset in the triangle's frame: the
    closest point on the mesh, exactly (a grid of cells of side h, each listing the triangles whose
    bounding box grown by h reaches it, finds it when it is within h; else every triangle is
    tried, nearest bounding sphere first)."""
    spheres = []
    boxes = []
    for (a, b, c) in triangles:
        pa, pb, pc = points[a], points[b], points[c]
        m = mul(add(add(pa, pb), pc), 1.0 / 3.0)
        spheres.append((m, max(norm(sub(pa, m)), norm(sub(pb, m)), norm(sub(pc, m)))))
        boxes.append([min(p[i] for p in (pa, pb, pc)) for i in range(3)] +
                     [max(p[i] for p in (pa, pb, pc)) for i in range(3)])
    h = max(radius for _, radius in spheres)
    grid = {}
    for t, box in enumerate(boxes):
        lo = [math.floor((box[i] - h) / h) for i in range(3)]
        hi = [math.floor((box[3 + i] + h) / h) for i in range(3)]
        for i in range(lo[0], hi[0] + 1):
            for j in range(lo[1], hi[1] + 1):
                for k in range(lo[2], hi[2] + 1):
                    grid.setdefault((i, j, k), []).append(t)

    def nearest(r, candidates):
        best = None
        for t in candidates:
            a, b, c = (points[k] for k in triangles[t])
            q, bary = closest_on_triangle(r, a, b, c)
            d = norm(sub(r, q))
            if best is None or d < best[0]:
                best = (d, t, bary, q)
        return best

    bindings = []
    for r in roots:
        cell = tuple(math.floor(r[i] / h) for i in range(3))
        best = nearest(r, grid.get(cell, []))
        if best is None or best[0] > h:
            best = None
            bounds = sorted((norm(sub(r, m)) - radius, t) for t, (m, radius) in enumerate(spheres))
            for bound, t in bounds:
                if best is not None and bound > best[0]:
                    break
                found = nearest(r, [t])
                if best is None or found[0] < best[0]:
                    best = found
        _, t, bary, q = best
        a, b, c = (points[k] for k in triangles[t])
        e1, e2, n = frame_of(a, b, c)
        o = sub(r, q)
        bindings.append((t, bary, (dot(o, e1), dot(o, e2), dot(o, n))))
    return bindings


def expected_root(binding, points, triangles, frames=None):
    """The root's barycentric point on `points` plus its offset turned with the triangle's frame
    (`frames`: a cache of the frames of these points' triangles)."""
    t, (u, v, w), (o1, o2, o3) = binding
    a, b, c = (points[k] for k in triangles[t])
    if frames is None:
        e1, e2, n = frame_of(a, b, c)
    else:
        if t not in frames:
            frames[t] = frame_of(a, b, c)
        e1, e2, n = frames[t]
    q = add(add(mul(a, u), mul(b, v)), mul(c, w))
    return add(q, add(add(mul(e1, o1), mul(e2, o2)), mul(n, o3)))


def world_of(prim, code, which=None):
    """A point-based prim's points at `code` (those numbered in `which`, default all) through its
    own transforms (the identity expected)."""
    points = UsdGeom.PointBased(prim).GetPointsAttr().Get(code)
    if which is not None:
        points = [points[i] for i in which]
    matrix = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(code)
    if matrix == Gf.Matrix4d(1.0):
        return [(float(p[0]), float(p[1]), float(p[2])) for p in points]
    return [tuple(matrix.Transform(Gf.Vec3d(p))) for p in points]


def check_export(name, path, codes, faces, reference, input_curves):
    """The export `path` against the input head `reference` {code: world points [m, Y up]}."""
    check(os.path.isfile(path), f"{name}: hairlod wrote {path}")
    try:
        stage = Usd.Stage.Open(path)
    except Exception as error:  # pxr raises Tf errors for a file it cannot parse
        check(False, f"{name}: Usd.Stage.Open({path}): {error}")
    check(stage is not None, f"{name}: Usd.Stage.Open({path})")
    check(UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y, f"{name}: upAxis Y")
    check(UsdGeom.GetStageMetersPerUnit(stage) == 1.0, f"{name}: metersPerUnit 1")
    tcps = stage.GetTimeCodesPerSecond()
    start, end = stage.GetStartTimeCode(), stage.GetEndTimeCode()
    check(tcps == CODES_PER_SECOND and start == codes[0] and end == codes[-1],
          f"{name}: timeCodesPerSecond {tcps:g} (want {CODES_PER_SECOND:g}), codes "
          f"{start:g}..{end:g} (want {codes[0]}..{codes[-1]})")

    hair_prim = stage.GetPrimAtPath("/hair")
    body_prim = stage.GetPrimAtPath("/body")
    check(hair_prim.IsValid() and hair_prim.IsA(UsdGeom.BasisCurves), f"{name}: /hair BasisCurves")
    check(body_prim.IsValid() and body_prim.IsA(UsdGeom.Mesh), f"{name}: /body Mesh")
    hair, body = UsdGeom.BasisCurves(hair_prim), UsdGeom.Mesh(body_prim)
    for label, attr in (("/hair", hair.GetPointsAttr()), ("/body", body.GetPointsAttr())):
        samples = attr.GetTimeSamples()
        shown = f"{samples[:3]}..{samples[-2:]}" if len(samples) > 5 else str(samples)
        check(samples == [float(c) for c in codes],
              f"{name}: {label} points sampled at codes {codes[0]}..{codes[-1]} "
              f"({len(samples)} samples: {shown})")

    # The body: the input's vertices, triangles cut from its polygons, facing outwards.
    counts = list(body.GetFaceVertexCountsAttr().Get())
    indices = list(body.GetFaceVertexIndicesAttr().Get())
    want = sum(len(f) - 2 for f in faces)
    check(all(c == 3 for c in counts) and len(counts) == want,
          f"{name}: /body has {len(counts)} triangles (want {want}, from {len(faces)} polygons)")
    triangles = [tuple(indices[3 * i:3 * i + 3]) for i in range(len(counts))]
    vertex_count = len(reference[codes[0]])
    polygons_of = {}  # vertex → the input polygons (vertex sets) that hold it
    for f in faces:
        for k in f:
            polygons_of.setdefault(k, []).append(frozenset(f))
    cut = all(any(set(t) <= p for p in polygons_of.get(t[0], [])) for t in triangles)
    check(cut and all(0 <= k < vertex_count for t in triangles for k in t),
          f"{name}: every /body triangle is cut from one input polygon")
    worst = (0.0, None)
    for code in codes:
        exported = world_of(body_prim, code)
        if len(exported) != vertex_count:
            check(False, f"{name}: /body has {len(exported)} points at code {code} "
                  f"(want {vertex_count})")
        for i, (p, q) in enumerate(zip(exported, reference[code])):
            d = norm(sub(p, q))
            if d > worst[0]:
                worst = (d, (code, i, p, q))
    detail = "" if worst[1] is None else (
        f" at code {worst[1][0]}, vertex {worst[1][1]}: {fmt(worst[1][2])} vs {fmt(worst[1][3])}")
    check(worst[0] <= BODY_TOLERANCE,
          f"{name}: /body equals the input head at every code within {BODY_TOLERANCE:g} m "
          f"(largest {worst[0]:.3g} m{detail})")
    first_points = world_of(body_prim, codes[0])
    centre = mul(tuple(map(sum, zip(*first_points))), 1.0 / vertex_count)
    inward = 0
    for t in triangles:
        a, b, c = (first_points[k] for k in t)
        if dot(cross(sub(b, a), sub(c, a)), sub(a, centre)) <= 0.0:
            inward += 1
    orientation = body.GetOrientationAttr().Get()
    if orientation == UsdGeom.Tokens.leftHanded:
        inward = len(triangles) - inward
    check(inward == 0, f"{name}: /body's triangles face outwards ({orientation}; "
          f"{inward} of {len(triangles)} face in)")

    # The roots.
    counts = list(hair.GetCurveVertexCountsAttr().Get())
    starts = []
    offset = 0
    for c in counts:
        starts.append(offset)
        offset += c
    check(len(counts) >= 1, f"{name}: /hair has {len(counts)} curves ({input_curves} in the "
          f"groom; {sum(counts)} points)")
    roots = {code: world_of(hair_prim, code, starts) for code in codes}
    bind_start = time.monotonic()
    bindings = bind_roots(roots[codes[0]], first_points, triangles)
    bound_in = time.monotonic() - bind_start
    largest_offset = max(norm(o) for _, _, o in bindings)
    print(f"  bound {len(bindings)} roots to /body at code {codes[0]} in {bound_in:.1f} s; "
          f"largest distance from the surface {largest_offset * 1e3:.3f} mm", flush=True)
    worst = (0.0, None)
    travel = 0.0
    for code in codes:
        body_points = world_of(body_prim, code)
        frames = {}
        for i, (binding, root) in enumerate(zip(bindings, roots[code])):
            d = norm(sub(root, expected_root(binding, body_points, triangles, frames)))
            if d > worst[0]:
                worst = (d, (code, i))
            travel = max(travel, norm(sub(root, roots[codes[0]][i])))
    detail = "" if worst[1] is None else f" (curve {worst[1][1]} at code {worst[1][0]})"
    check(worst[0] <= ROOT_TOLERANCE,
          f"{name}: every root within {ROOT_TOLERANCE * 1e3:g} mm of its code-{codes[0]} "
          f"barycentric point on the deformed /body at every code: largest "
          f"{worst[0] * 1e3:.4f} mm{detail}; largest offset from the surface at code "
          f"{codes[0]} {largest_offset * 1e3:.4f} mm")
    check(travel > MIN_ROOT_TRAVEL,
          f"{name}: the roots move with the body (largest travel {travel * 1e3:.1f} mm, "
          f"> {MIN_ROOT_TRAVEL * 1e3:g} mm)")


def fmt(p):
    return "(" + ", ".join(f"{c:.6f}" for c in p) + ")"


def run_usd(binary, folder):
    os.makedirs(folder, exist_ok=True)
    body, faces, reference, curves = write_usd_character(folder)
    check(True, f"usd: wrote {body} ({len(faces)} polygons = "
          f"{sum(len(f) - 2 for f in faces)} triangles, {curves} curves of {CURVE_POINTS} points, "
          f"{FRAMES} codes)")
    scene = write_scene(folder, "character.usda", "character.usda")
    out = os.path.join(folder, "out")
    elapsed = render(binary, scene, out)
    check_export("usd", os.path.join(out, "hair.usda"), CODES, faces, reference, curves)
    return elapsed


def run_abc(binary, folder):
    os.makedirs(folder, exist_ok=True)
    body, groom, faces, reference, curves = write_abc_character(folder)
    check(True, f"abc: wrote {body} and {groom} ({curves} curves)")
    scene = write_scene(folder, "groom.usda", "character.abc")
    out = os.path.join(folder, "out")
    elapsed = render(binary, scene, out)
    check_export("abc", os.path.join(out, "hair.usda"), CODES, faces, reference, curves)
    return elapsed


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary", help="the hairlod binary (target/debug/hairlod)")
    parser.add_argument("--keep", metavar="DIR", help="write into DIR and keep it")
    parser.add_argument("--only", choices=("usd", "abc"), help="run one of the two characters")
    args = parser.parse_args()
    binary = os.path.abspath(args.binary)
    check(os.path.isfile(binary) and os.access(binary, os.X_OK), f"hairlod binary {binary}")
    if args.keep:
        folder = os.path.abspath(args.keep)
        os.makedirs(folder, exist_ok=True)
    else:
        folder = tempfile.mkdtemp(prefix="hairlod-character-")
    try:
        timings = {}
        if args.only in (None, "usd"):
            timings["usd"] = run_usd(binary, os.path.join(folder, "usd"))
        if args.only in (None, "abc"):
            timings["abc"] = run_abc(binary, os.path.join(folder, "abc"))
        print("all character checks passed; render times: " +
              ", ".join(f"{k} {v:.1f} s" for k, v in timings.items()))
    finally:
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
