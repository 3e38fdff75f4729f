"""ParaView opens a run's output as a user would: OpenDataFile (the default reader), then checks
arrays, time steps and values against output.h5, contours and stream-traces the fluid, and saves a
screenshot. Run by ctest (label paraview) as

    xvfb-run -a pvpython tests/paraview/check_paraview.py SPHIB SOURCE_DIR WORK_DIR

It runs two short cases with SPHIB into WORK_DIR: the oscillating membrane with EPSPH (fixed
lattice: a mesh of quadrilaterals, membranes in output_membranes.xdmf) and with LPSPH (moving
particles: vertices). The screenshot, drawn by scripts/paraview_picture.py (the README's command),
is WORK_DIR/paraview_oscillation.png.
"""
import os
import subprocess
import sys

import h5py
import numpy as np
from paraview.simple import Contour, GetActiveViewOrCreate, GetDisplayProperties, OpenDataFile, XDMFReader
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkIOImage import vtkPNGReader

failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what, flush=True)
    if not ok:
        failures.append(what)


def run(sphib, scene, out, *sets):
    cmd = [sphib, "run", scene, "--out", out, "--quiet"] + [a for s in sets for a in ("--set", s)]
    subprocess.run(cmd, check=True)


def snapshots(h5):
    """(time, group) of every snapshot in output.h5, in time order."""
    groups = [h5["snapshots"][k] for k in sorted(h5["snapshots"])]
    return [(float(g.attrs["time"]), g) for g in groups]


def leaves(reader, t):
    """The datasets (leaves) the reader gives at time t, wrapped for NumPy."""
    reader.UpdatePipeline(t)
    out = reader.GetClientSideObject().GetOutputDataObject(0)
    if not out.IsA("vtkCompositeDataSet"):
        return [dsa.WrapDataObject(out)]
    it = out.NewIterator()
    it.InitTraversal()
    result = []
    while not it.IsDoneWithTraversal():
        result.append(dsa.WrapDataObject(it.GetCurrentDataObject()))
        it.GoToNextItem()
    return result


def same(a, b):
    return a.shape == b.shape and np.array_equal(a, b)


def check_fluid(path, h5path, kind):
    """kind: 'lattice' (EPSPH, a quadrilateral mesh) or 'particles' (LPSPH, vertices)."""
    reader = OpenDataFile(path)
    name = reader.GetXMLName()
    check(name.startswith("Xdmf3Reader"), f"{kind}: the default reader is Xdmf3 ({name})")
    with h5py.File(h5path, "r") as h5:
        snaps = snapshots(h5)
        times = list(reader.TimestepValues) if len(snaps) > 1 else [reader.TimestepValues]
        reader.UpdatePipeline(times[0])
        check(np.allclose(times, [t for t, _ in snaps], rtol=0, atol=1e-15),
              f"{kind}: {len(times)} time steps, those of /snapshots ({len(snaps)})")
        names = sorted(reader.PointData.keys())
        fields = sorted(k for k in ("u", "v", "p", "phi") if k in snaps[0][1])
        check(names == sorted(fields + ["velocity"]), f"{kind}: point arrays {names}")
        for t, g in snaps:
            blocks = leaves(reader, t)
            check(len(blocks) == 1, f"{kind} t = {t:g}: one dataset ({len(blocks)})")
            b = blocks[0]
            x = np.column_stack([g["x"][:], g["y"][:], np.zeros(len(g["x"]))])
            check(same(np.asarray(b.Points), x), f"{kind} t = {t:g}: {len(x)} points at /x, /y, in their order")
            if kind == "lattice":
                nx = int(round((x[:, 0].max() - x[:, 0].min()) / (x[1, 0] - x[0, 0]))) + 1
                ny = len(x) // nx
                check(b.GetNumberOfCells() == (nx - 1) * (ny - 1), f"lattice t = {t:g}: {(nx - 1) * (ny - 1)} quads")
            else:
                check(b.GetNumberOfCells() == len(x), f"particles t = {t:g}: one vertex per particle")
            for f in fields:
                check(same(np.asarray(b.PointData[f]), g[f][:]), f"{kind} t = {t:g}: {f} equals /snapshots/{f}")
            vel = np.column_stack([g["u"][:], g["v"][:], np.zeros(len(x))])
            check(same(np.asarray(b.PointData["velocity"]), vel), f"{kind} t = {t:g}: velocity = (u, v, 0)")
    return reader


def check_membranes(path, h5path):
    reader = OpenDataFile(path)
    with h5py.File(h5path, "r") as h5:
        snaps = snapshots(h5)
        check(np.allclose(reader.TimestepValues, [t for t, _ in snaps], rtol=0, atol=1e-15),
              f"membranes: time steps of /snapshots ({len(snaps)})")
        reader.UpdatePipeline(snaps[0][0])
        check(sorted(reader.PointData.keys()) == ["T", "f"], f"membranes: arrays {sorted(reader.PointData.keys())}")
        for t, g in snaps:
            blocks = leaves(reader, t)
            m = g["membrane_0"]
            nb = len(m["T"])
            check(len(blocks) == 1 and blocks[0].GetNumberOfCells() == 1,
                  f"membranes t = {t:g}: one closed polyline")
            b = blocks[0]
            X = np.column_stack([m["X"][:], np.zeros(nb)])
            check(same(np.asarray(b.Points), X), f"membranes t = {t:g}: {nb} markers at membrane_0/X")
            check(same(np.asarray(b.PointData["T"]), m["T"][:]), f"membranes t = {t:g}: T equals membrane_0/T")
            check(same(np.asarray(b.PointData["f"]), m["f3"][:]), f"membranes t = {t:g}: f equals membrane_0/f")
            ids = b.GetCell(0).GetPointIds()
            check(ids.GetNumberOfIds() == nb + 1 and ids.GetId(0) == ids.GetId(nb), f"membranes t = {t:g}: closed")
    return reader


def main():
    sphib, source, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)

    # EPSPH: the main case, shortened, 64 x 64, five snapshots.
    epsph = os.path.join(work, "oscillation")
    run(sphib, os.path.join(source, "cases/membrane_oscillation.toml"), epsph,
        "time.end=0.2", "output.interval=0.05")
    h5 = os.path.join(epsph, "output.h5")
    fluid = check_fluid(os.path.join(epsph, "output.xdmf"), h5, "lattice")
    check_membranes(os.path.join(epsph, "output_membranes.xdmf"), h5)
    t_end = fluid.TimestepValues[-1]

    # The legacy reader the issue used opens the same files.
    legacy = XDMFReader(FileNames=[os.path.join(epsph, "output.xdmf")])
    legacy.PointArrayStatus = ["p", "u", "v", "velocity"]
    legacy.UpdatePipelineInformation()
    with h5py.File(h5, "r") as f:
        t, g = snapshots(f)[-1]
        b = leaves(legacy, t)
        check(len(b) == 1 and same(np.asarray(b[0].PointData["p"]), g["p"][:]),
              f"legacy XDMFReader: p at t = {t:g} equals the HDF5 file")

    # A user's first filter: contours of p.
    fluid.UpdatePipeline(t_end)
    lo, hi = fluid.PointData["p"].GetRange()
    contour = Contour(Input=fluid, ContourBy=["POINTS", "p"], Isosurfaces=[0.5 * (lo + hi)])
    contour.UpdatePipeline(t_end)
    check(contour.GetDataInformation().GetNumberOfCells() > 20, "contour of p: a curve of line segments")

    # The picture the README's command draws: p as a coloured surface, streamlines, the membrane by T.
    png = os.path.join(work, "paraview_oscillation.png")
    sys.path.insert(0, os.path.join(source, "scripts"))
    import paraview_picture
    sources = paraview_picture.picture(epsph, png)
    trace = sources[1]
    n_trace = trace.GetDataInformation().GetNumberOfPoints()
    check(n_trace > 300, f"stream tracer on velocity: streamlines ({n_trace} points)")
    view = GetActiveViewOrCreate("RenderView")
    shown = [GetDisplayProperties(src, view).Representation for src in sources]
    check(shown == ["Surface"] * 3,
          f"fluid, streamlines and membranes drawn by the default representation ({shown})")
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = dsa.WrapDataObject(r.GetOutput()).PointData[0][:, :3]
    colours = len(np.unique(img.astype(np.int64) @ np.array([1 << 16, 1 << 8, 1])))
    check(colours > 500, f"the screenshot is a coloured field ({colours} colours)")

    # LPSPH: moving particles as vertices.
    lpsph = os.path.join(work, "oscillation_lagrangian")
    run(sphib, os.path.join(source, "cases/membrane_oscillation_lagrangian.toml"), lpsph,
        "grid.nx=32", "grid.ny=32", "membrane.nb=64", "time.end=0.0003", "output.interval=0.0001")
    check_fluid(os.path.join(lpsph, "output.xdmf"), os.path.join(lpsph, "output.h5"), "particles")

    print(f"{len(failures)} failed: screenshot {png}" if failures else f"all passed; screenshot {png}", flush=True)
    # Leave without ParaView's teardown, which under Xvfb can end in an X error (GLXBadContext) and
    # exit status 1 after everything passed.
    os._exit(1 if failures else 0)


if __name__ == "__main__":
    main()
