#!/usr/bin/env python3
"""Writes crates/hair-formats/tests/data/curves.abc and no_curves.abc, the Alembic (Ogawa) fixtures of
the `.abc` reader.

Needs PyAlembic; the unofficial wheel on PyPI works (import name `alembic3d`):

    python3 -m venv /tmp/abcvenv && /tmp/abcvenv/bin/pip install alembic3d==1.8.12.1
    /tmp/abcvenv/bin/python crates/hair-formats/tests/make_alembic_fixture.py

The archive (values the tests in src/tests/alembic.rs check):

    /plain        Curves, linear, 3 curves of 3, 1 and 2 points, one constant width 0.1
                  (the one-point curve is degenerate: skipped, or refused when strict)
    /groom        Xform: translate (10, 20, 30), then scale (2, 2, 2)
    /groom/tuft   Curves, linear, 2 curves of 3 points with a width per point,
                  two time samples (the second moved by +100 in x: the reader takes the first)

no_curves.abc holds one Xform, /empty, and no Curves object.
"""

import os
import sys

import imath
from alembic3d import Abc, AbcCoreAbstract, AbcGeom

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
OUT = os.path.join(DATA, "curves.abc")
NO_CURVES = os.path.join(DATA, "no_curves.abc")


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


def float_array(values):
    array = imath.FloatArray(len(values))
    for i, v in enumerate(values):
        array[i] = v
    return array


def curves_sample(points, counts, widths, scope):
    sample = AbcGeom.OCurvesSchemaSample(
        v3f_array(points), int_array(counts), AbcGeom.CurveType.kLinear
    )
    sample.setWidths(AbcGeom.OFloatGeomParamSample(float_array(widths), scope))
    return sample


PLAIN_POINTS = [(0, 0, 0), (0, 1, 0), (0, 2, 0.5), (5, 5, 5), (1, 0, 0), (1, 0.25, 0)]
PLAIN_COUNTS = [3, 1, 2]
PLAIN_WIDTHS = [0.1]
TUFT_POINTS = [(0, 0, 0), (0, 1, 0), (0, 2, 0), (1, 0, 0), (1, 1, 0), (1, 2, 0.5)]
TUFT_COUNTS = [3, 3]
TUFT_WIDTHS = [0.5, 0.25, 0.125, 0.5, 0.25, 0.0]


def main():
    archive = Abc.OArchive(OUT)  # Ogawa, the default
    top = archive.getTop()

    plain = AbcGeom.OCurves(top, "plain")
    constant = AbcGeom.GeometryScope.kConstantScope
    plain.getSchema().set(curves_sample(PLAIN_POINTS, PLAIN_COUNTS, PLAIN_WIDTHS, constant))

    groom = AbcGeom.OXform(top, "groom")
    xform = AbcGeom.XformSample()
    xform.setTranslation(imath.V3d(10, 20, 30))
    xform.setScale(imath.V3d(2, 2, 2))
    groom.getSchema().set(xform)

    time = AbcCoreAbstract.TimeSampling(1.0 / 24.0, 0.0)
    index = archive.addTimeSampling(time)
    tuft = AbcGeom.OCurves(groom, "tuft", index)
    vertex = AbcGeom.GeometryScope.kVertexScope
    tuft.getSchema().set(curves_sample(TUFT_POINTS, TUFT_COUNTS, TUFT_WIDTHS, vertex))
    moved = [(x + 100, y, z) for (x, y, z) in TUFT_POINTS]
    tuft.getSchema().set(curves_sample(moved, TUFT_COUNTS, TUFT_WIDTHS, vertex))
    del archive, top, plain, groom, tuft
    print(f"wrote {OUT}", file=sys.stderr)

    archive = Abc.OArchive(NO_CURVES)
    AbcGeom.OXform(archive.getTop(), "empty").getSchema().set(AbcGeom.XformSample())
    del archive
    print(f"wrote {NO_CURVES}", file=sys.stderr)


if __name__ == "__main__":
    main()
