"""A picture of a run with ParaView: the pressure as a coloured surface, streamlines of the
velocity, the membranes coloured by their tension T. Opens DIR/output.xdmf and, when the run has
membranes, DIR/output_membranes.xdmf with ParaView's default reader (OpenDataFile).

    xvfb-run -a pvpython scripts/paraview_picture.py out/membrane_oscillation [--time 0.5] [--png FILE]

(xvfb-run: no display needed; without it pvpython opens a window.) Writes DIR/paraview.png unless
--png says otherwise. Needs Debian's paraview and python3-paraview (and xvfb for xvfb-run).
"""
import argparse
import os

from paraview.simple import (ColorBy, GetActiveViewOrCreate, OpenDataFile, Render, ResetCamera, SaveScreenshot,
                             Show, StreamTracer)


def picture(run_dir, png, time=None, size=(900, 800)):
    """Renders the run at `time` (default: its last output) into png; returns the sources
    (fluid, streamlines, membranes or None)."""
    fluid = OpenDataFile(os.path.join(run_dir, "output.xdmf"))
    times = fluid.TimestepValues
    times = list(times) if isinstance(times, (list, tuple)) or hasattr(times, "__len__") else [times]
    t = times[-1] if time is None else min(times, key=lambda s: abs(s - time))
    fluid.UpdatePipeline(t)
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = list(size)
    view.ViewTime = t
    view.OrientationAxesVisibility = 0
    d = Show(fluid, view)
    colour = "p" if "p" in fluid.PointData.keys() else fluid.PointData.keys()[0]
    ColorBy(d, ("POINTS", colour))
    d.RescaleTransferFunctionToDataRange(False, True)
    d.SetScalarBarVisibility(view, True)
    trace = None
    if "velocity" in fluid.PointData.keys():  # seeds on a diagonal of the domain, in its plane
        (x0, x1, y0, y1, _, _) = fluid.GetDataInformation().GetBounds()
        trace = StreamTracer(Input=fluid, Vectors=["POINTS", "velocity"], SeedType="Line")
        trace.SeedType.Point1 = [x0 + 0.02 * (x1 - x0), y1 - 0.1 * (y1 - y0), 0.0]
        trace.SeedType.Point2 = [x1 - 0.02 * (x1 - x0), y0 + 0.1 * (y1 - y0), 0.0]
        trace.SeedType.Resolution = 39  # 40 seeds, none at the centre (a symmetry axis)
        s = Show(trace, view)
        s.ColorArrayName = [None, ""]
        s.AmbientColor = s.DiffuseColor = [0.1, 0.1, 0.1]
    membranes = None
    path = os.path.join(run_dir, "output_membranes.xdmf")
    if os.path.exists(path):
        membranes = OpenDataFile(path)
        m = Show(membranes, view)
        ColorBy(m, ("POINTS", "T"))
        m.LineWidth = 4.0
        m.RescaleTransferFunctionToDataRange(False, True)
        m.SetScalarBarVisibility(view, True)
        m.Position = [0, 0, 0.01]  # above the surface
    view.InteractionMode = "2D"
    ResetCamera(view)
    Render(view)
    SaveScreenshot(png, view, ImageResolution=list(size))
    return fluid, trace, membranes


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description="a picture of a sphib run with ParaView")
    ap.add_argument("run_dir", help="the run's output directory (output.xdmf)")
    ap.add_argument("--time", type=float, default=None, help="output time to draw (default: the last)")
    ap.add_argument("--png", default=None, help="image file (default: RUN_DIR/paraview.png)")
    a = ap.parse_args()
    png = a.png or os.path.join(a.run_dir, "paraview.png")
    picture(a.run_dir, png, a.time)
    print(png, flush=True)
    os._exit(0)  # ParaView's teardown under Xvfb can end in an X error after the picture is written
