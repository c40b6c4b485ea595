#!/usr/bin/python3
"""How well do the paper's two weight terms predict the error that removing a vertex causes?

    diagnose.py SURFACE.vtp [SURFACE.vtp ...]
    diagnose.py --edges REDUCED.vtp [REDUCED.vtp ...]

For every interior manifold vertex v of the input (one-ring closed, no boundary) it computes
  - curv(v): the angle deficit |2pi - sum theta| / pi (the paper's curvature term,
    Terms::AngleDeficitGradient), and
    plane(v): the distance from v to the plane of its ring (centroid, area-weighted normal) over
    the mean ring edge length: what removing v does to the geometry (vtkDecimatePro's criterion);
  - grad(v): max_i |f_i - f|_1 / |x_i - x|_1 with each field divided by its range and lengths by
    the bounding-box diagonal (ddsimp's data term), and
    lap(v): |f(v) - mean_i f_i|_1 / range: how far v's value is from what the ring would
    interpolate there, i.e. the data error removing v causes (to first order).
and prints Spearman's rank correlation of each term with the error it stands for, and the share of
vertices that the term ranks in its lightest quarter although their error is in the worst quarter
(removed early although they matter). With --edges it prints, for reduced surfaces, how uneven
their edge lengths are (median, 99th percentile and longest, relative to the bounding-box
diagonal): a weight that does not grow as a region gets coarser leaves a few huge triangles.
Needs python3-vtk9, numpy, scipy.
"""

import sys

import numpy as np
import vtk
from scipy.stats import spearmanr
from vtk.util.numpy_support import vtk_to_numpy


def load(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    poly = reader.GetOutput()
    points = vtk_to_numpy(poly.GetPoints().GetData()).astype(np.float64)
    cells = vtk_to_numpy(poly.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    fields = []
    pd = poly.GetPointData()
    for i in range(pd.GetNumberOfArrays()):
        a = vtk_to_numpy(pd.GetArray(i)).astype(np.float64)
        a = a.reshape(len(points), -1)
        rng = (a.max(axis=0) - a.min(axis=0)).max()
        if rng > 0:
            fields.append(a / rng)
    return points, cells, np.hstack(fields) if fields else None


def analyse(path):
    x, tris, f = load(path)
    n = len(x)
    diagonal = np.linalg.norm(x.max(axis=0) - x.min(axis=0))
    # Corner angles and the rings, from the triangle list.
    angle_sum = np.zeros(n)
    ring = [set() for _ in range(n)]
    edge_count = {}
    normal = np.zeros((n, 3))
    for t in tris:
        for k in range(3):
            a, b, c = t[k], t[(k + 1) % 3], t[(k + 2) % 3]
            u, w = x[b] - x[a], x[c] - x[a]
            cosang = np.dot(u, w) / (np.linalg.norm(u) * np.linalg.norm(w) + 1e-300)
            angle_sum[a] += np.arccos(np.clip(cosang, -1, 1))
            ring[a].update((b, c))
            e = (min(a, b), max(a, b))
            edge_count[e] = edge_count.get(e, 0) + 1
        nrm = np.cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]])
        for v in t:
            normal[v] += nrm
    on_boundary = np.zeros(n, bool)
    for (a, b), count in edge_count.items():
        if count != 2:
            on_boundary[a] = on_boundary[b] = True
    rows = []
    for v in range(n):
        r = list(ring[v])
        if on_boundary[v] or len(r) < 3:
            continue
        xr = x[r]
        lengths = np.linalg.norm(xr - x[v], axis=1)
        nv = normal[v] / (np.linalg.norm(normal[v]) + 1e-300)
        curv = abs(2 * np.pi - angle_sum[v]) / np.pi
        plane = abs(np.dot(x[v] - xr.mean(axis=0), nv)) / lengths.mean()
        if f is not None:
            l1 = np.abs(xr - x[v]).sum(axis=1) / diagonal
            grad = (np.abs(f[r] - f[v]).sum(axis=1) / np.maximum(l1, 1e-300)).max()
            lap = np.abs(f[v] - f[r].mean(axis=0)).sum()
        else:
            grad = lap = np.nan
        rows.append((curv, plane, grad, lap))
    a = np.array(rows)

    def report(term, error, name):
        rho = spearmanr(term, error).correlation
        light = term <= np.quantile(term, 0.25)
        bad = error >= np.quantile(error, 0.75)
        zero = np.mean(term < 0.01)
        print(f"  {name}: Spearman {rho:+.2f}; lightest quarter holding worst-quarter errors: "
              f"{np.mean(light & bad) / np.mean(light):.0%} (25% if unrelated); term < 0.01 at "
              f"{zero:.0%} of vertices")

    print(f"{path}: {len(a)} interior vertices")
    report(a[:, 0], a[:, 1], "curv vs plane distance")
    if f is not None:
        report(a[:, 2], a[:, 3], "grad vs data Laplacian")


def edges(path):
    x, tris, _ = load(path)
    diagonal = np.linalg.norm(x.max(axis=0) - x.min(axis=0))
    e = np.concatenate([np.linalg.norm(x[tris[:, k]] - x[tris[:, (k + 1) % 3]], axis=1)
                        for k in range(3)]) / diagonal
    print(f"{path}: {len(tris)} triangles, edge / diagonal: median {np.median(e):.4f}, "
          f"99th percentile {np.quantile(e, 0.99):.4f}, longest {e.max():.4f}, "
          f"longest / median {e.max() / np.median(e):.1f}")


if len(sys.argv) > 1 and sys.argv[1] == "--edges":
    for p in sys.argv[2:]:
        edges(p)
else:
    for p in sys.argv[1:]:
        analyse(p)
