"""The revolved 3-D view of an axisymmetric (meridian) run, with ParaView (run with pvpython).

Usage: [xvfb-run -a] pvpython scripts/revolve.py RUN_DIR [--time T] [--field p]
                [--angle 270] [--png FILE] [--vtu FILE]

--png renders, and Debian's ParaView renders through X: without a display (a server, a
container, an ssh session without X forwarding) it crashes with SIGSEGV, even with
--force-offscreen-rendering. Run it under a virtual display, `xvfb-run -a pvpython ...`
(ci/setup-paraview.sh installs xvfb with ParaView); the script refuses --png without one. --vtu
and the printed sizes need no display.

The meridian lies in the x-z plane (x = r). The pipeline is the one to build in the ParaView GUI:
XDMF reader -> Warp By Vector (u, in the meridian plane, before revolving) -> Extract Surface ->
Rotational Extrusion about z (Angle < 360 with Capping on leaves a cut open, showing the field on
the meridian). --png renders it (a still, coloured by --field); --vtu saves the revolved surface.
Prints the revolved surface's size and bounds.
"""
import argparse
import os
import sys

FIX = "run it under a virtual display: xvfb-run -a pvpython scripts/revolve.py ... (ci/setup-paraview.sh installs xvfb)"


def renders_through_x():
    """Whether this ParaView renders through X (Debian's build) rather than off-screen (an EGL or
    OSMesa build); when it cannot tell, X. Creating a render window opens no display."""
    try:
        import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (registers the platform's window)
        from vtkmodules.vtkRenderingCore import vtkRenderWindow
        return "XOpenGL" in vtkRenderWindow().GetClassName()
    except Exception:
        return True


def no_display():
    """Why ParaView cannot render here (None if it can): on Linux without a display, a ParaView
    that renders through X crashes (SIGSEGV) instead of saying so."""
    if sys.platform.startswith("linux") and not os.environ.get("DISPLAY") and renders_through_x():
        return "no display (DISPLAY is not set), and this ParaView's rendering crashes without one"
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run_dir")
    ap.add_argument("--time", type=float, default=None, help="time to show (default: the last step)")
    ap.add_argument("--field", default="p", help="point field to colour by (p, contact, ...)")
    ap.add_argument("--angle", type=float, default=270.0, help="sweep angle in degrees")
    ap.add_argument("--png", default=None)
    ap.add_argument("--vtu", default=None)
    a = ap.parse_args()
    xdmf = os.path.join(os.path.abspath(a.run_dir), "fields.xdmf")
    if not os.path.isfile(xdmf):
        sys.exit(f"revolve.py: {xdmf} does not exist: give a run directory with fields (output.fields = true)")
    why = no_display() if a.png else None
    if why:
        sys.exit(f"revolve.py: --png renders, but there is {why}: {FIX}. (--vtu needs no display.)")
    try:
        from paraview import servermanager as sm
        from paraview import simple
    except ImportError:
        sys.exit("revolve.py: ParaView's Python modules are not here: run it with ParaView's pvpython "
                 "(pvpython scripts/revolve.py ...; ci/setup-paraview.sh installs it)")
    reader = simple.Xdmf3ReaderT(FileName=[xdmf])
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues or [0.0])
    t = times[-1] if a.time is None else min(times, key=lambda s: abs(s - a.time))
    warp = simple.WarpByVector(Input=reader, Vectors=["POINTS", "u"])
    surface = simple.ExtractSurface(Input=warp)
    revolved = simple.RotationalExtrusion(Input=surface, Angle=a.angle, Resolution=72, Capping=1)
    revolved.UpdatePipeline(t)
    d = sm.Fetch(revolved)
    bounds = [round(b, 3) for b in d.GetBounds()]
    print(f"revolve: t = {t}: {d.GetNumberOfPoints()} points, {d.GetNumberOfCells()} cells, bounds {bounds}")
    if a.vtu:
        simple.SaveData(a.vtu, proxy=revolved)
    if a.png:
        view = simple.CreateView("RenderView")
        view.ViewSize = [900, 700]
        view.ViewTime = t
        disp = simple.Show(revolved, view)
        simple.ColorBy(disp, ("POINTS", a.field))
        disp.RescaleTransferFunctionToDataRange(True, False)
        disp.SetScalarBarVisibility(view, True)
        view.CameraPosition = [500.0, -700.0, 350.0]
        view.CameraFocalPoint = [0.0, 0.0, 100.0]
        view.CameraViewUp = [0.0, 0.0, 1.0]
        view.ResetCamera()
        simple.SaveScreenshot(a.png, view, ImageResolution=[900, 700])
        print(f"revolve: wrote {a.png}")


if __name__ == "__main__":
    main()
