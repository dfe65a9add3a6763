#!/usr/bin/env python3
"""Writes crates/hair-formats/tests/data/mesh_sequence.abc, the Alembic (Ogawa) fixture of the
Alembic mesh sequence reader (src/tests/mesh_sequence.rs).

Needs PyAlembic; the unofficial wheel on PyPI works (import name `alembic3d`):

    python3 -m venv /tmp/abcvenv && /tmp/abcvenv/bin/pip install alembic3d==1.8.12.1
    /tmp/abcvenv/bin/python crates/hair-formats/tests/make_alembic_mesh_fixture.py

The archive, one uniform time sampling: start 0.5 s, 1/24 s per sample, 3 samples (i = 0, 1, 2 at
0.5, 0.5 + 1/24, 0.5 + 2/24 s):

    /body         Xform, at sample i: translate (10 i, 0, 0), then rotate about Z by 90 i degrees
                  (a point p goes to T(10 i, 0, 0) · Rz(90 i°) · p)
    /body/skin    PolyMesh, one quad, faceCounts [4], faceIndices [0, 3, 2, 1] (Alembic's
                  clockwise winding seen from +Z: the face's front is +Z), at sample i
                  P = (0, 0.5 i, 0), (1, 0.5 i, 0), (1 + i, 1 + 0.5 i, 0), (0, 1 + 0.5 i, 0)
    /still        PolyMesh, one triangle (0, 0, 5), (0, 1, 5), (1, 0, 5) (clockwise seen from +Z),
                  one sample, no transform

mesh_topology_change.abc holds one PolyMesh, /blob, whose second sample (at 1/24 s; the first is
at 0 s) has a quad where the first has a triangle: the reader refuses it.

So in the world, sample 1 of the quad's point 2, (2, 1.5, 0), is Rz(90°)·(2, 1.5, 0) + (10, 0, 0)
= (8.5, 2, 0); sample 2's, (3, 2, 0), is Rz(180°)·(3, 2, 0) + (20, 0, 0) = (17, -2, 0).
"""

import os
import sys

import imath
from alembic3d import Abc, AbcCoreAbstract, AbcGeom

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
OUT = os.path.join(DATA, "mesh_sequence.abc")
TOPOLOGY = os.path.join(DATA, "mesh_topology_change.abc")


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


def quad(i):
    y = 0.5 * i
    return [(0, y, 0), (1, y, 0), (1 + i, 1 + y, 0), (0, 1 + y, 0)]


def main():
    archive = Abc.OArchive(OUT)  # Ogawa, the default
    top = archive.getTop()
    time = AbcCoreAbstract.TimeSampling(1.0 / 24.0, 0.5)
    index = archive.addTimeSampling(time)

    body = AbcGeom.OXform(top, "body", index)
    skin = AbcGeom.OPolyMesh(body, "skin", index)
    for i in range(3):
        xform = AbcGeom.XformSample()
        xform.setTranslation(imath.V3d(10 * i, 0, 0))
        xform.setZRotation(90 * i)
        body.getSchema().set(xform)
        sample = AbcGeom.OPolyMeshSchemaSample(
            v3f_array(quad(i)), int_array([0, 3, 2, 1]), int_array([4])
        )
        skin.getSchema().set(sample)
        print(i, xform.getMatrix(), file=sys.stderr)

    still = AbcGeom.OPolyMesh(top, "still")
    still.getSchema().set(
        AbcGeom.OPolyMeshSchemaSample(
            v3f_array([(0, 0, 5), (0, 1, 5), (1, 0, 5)]), int_array([0, 1, 2]), int_array([3])
        )
    )
    del archive, top, body, skin, still
    print(f"wrote {OUT} ({os.path.getsize(OUT)} bytes)", file=sys.stderr)

    archive = Abc.OArchive(TOPOLOGY)
    index = archive.addTimeSampling(AbcCoreAbstract.TimeSampling(1.0 / 24.0, 0.0))
    blob = AbcGeom.OPolyMesh(archive.getTop(), "blob", index)
    square = [(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)]
    blob.getSchema().set(
        AbcGeom.OPolyMeshSchemaSample(v3f_array(square), int_array([0, 1, 2]), int_array([3]))
    )
    blob.getSchema().set(
        AbcGeom.OPolyMeshSchemaSample(v3f_array(square), int_array([0, 1, 2, 3]), int_array([4]))
    )
    del archive, blob
    print(f"wrote {TOPOLOGY} ({os.path.getsize(TOPOLOGY)} bytes)", file=sys.stderr)


if __name__ == "__main__":
    main()
