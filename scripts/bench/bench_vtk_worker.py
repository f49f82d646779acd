#!/usr/bin/python3
"""VTK's CPU ray caster (vtkFixedPointVolumeRayCastMapper) on the benchmark views, for
scripts/bench/bench_raycaster.py and scripts/bench/bench_march.sh.

Usage: xvfb-run -a /usr/bin/python3 scripts/bench/bench_vtk_worker.py JOB.json
JOB.json: {"volume": NRRD, "camera": {"position", "look_at", "up", "fov", "size": "WxH"},
"threads": N, "tasks": [{"mode": "iso"|"composite", "iso": HU, "step_mm": S, "runs": R,
"png": OUT}, ...], "result": RESULT.json}. Writes RESULT.json: VTK's version and per task the
first render's seconds and the timed renders' milliseconds; each task's image to its png.
Needs Debian's python3-vtk9, python3-numpy, python3-pil and an X server (xvfb-run).
"""
import json
import sys
import time

import numpy as np

from bench_images import read_nrrd, spacing_of, write_png


def vtk_worker(job_path):
    """Renders each job with vtkFixedPointVolumeRayCastMapper: first render (untimed: it builds
    the gradient normals and space-leaping tables), then `runs` timed renders."""
    import vtk
    from vtk.util import numpy_support
    job = json.load(open(job_path))
    fields, hu = read_nrrd(job["volume"])
    spacing = spacing_of(fields)
    image = vtk.vtkImageData()
    image.SetDimensions(hu.shape[2], hu.shape[1], hu.shape[0])
    image.SetSpacing(*spacing)
    image.SetOrigin(0.0, 0.0, 0.0)  # so that VTK's world coordinates are our volume millimetres
    scalars = numpy_support.numpy_to_vtk(np.ascontiguousarray(hu).ravel(), deep=True, array_type=vtk.VTK_SHORT)
    image.GetPointData().SetScalars(scalars)

    cam = job["camera"]
    width, height = (int(s) for s in cam["size"].split("x"))
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(width, height)
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(0.015, 0.017, 0.022)
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*[float(x) for x in cam["position"].split(",")])
    camera.SetFocalPoint(*[float(x) for x in cam["look_at"].split(",")])
    camera.SetViewUp(*[float(x) for x in cam["up"].split(",")])
    camera.SetViewAngle(float(cam["fov"]))
    extent = np.array(hu.shape[::-1]) * np.array(spacing)
    camera.SetClippingRange(0.05 * min(spacing), 4.0 * float(np.linalg.norm(extent)))
    renderer.LightFollowCameraOn()  # the default light is a headlight at the camera

    mucosa, tissue = (0.93, 0.60, 0.50), (0.80, 0.45, 0.38)
    results = []
    for task in job["tasks"]:
        mapper = vtk.vtkFixedPointVolumeRayCastMapper()
        mapper.SetInputData(image)
        mapper.SetBlendModeToComposite()
        mapper.SetAutoAdjustSampleDistances(0)
        mapper.SetLockSampleDistanceToInputSpacing(0)
        mapper.SetImageSampleDistance(1.0)
        mapper.SetSampleDistance(task["step_mm"])
        mapper.SetNumberOfThreads(job["threads"])
        colour = vtk.vtkColorTransferFunction()
        opacity = vtk.vtkPiecewiseFunction()
        if task["mode"] == "composite":  # our colon-wall preset
            for h, c, a in ((-1024, mucosa, 0.0), (-650, mucosa, 0.0), (-500, mucosa, 0.6), (-350, tissue, 1.0),
                            (3071, tissue, 1.0)):
                colour.AddRGBPoint(h, *c)
                opacity.AddPoint(h, a)
        else:  # iso-surface-like: a surface that turns opaque within 30 HU of the iso value
            iso = task["iso"]
            for h, a in ((-1024, 0.0), (iso - 30, 0.0), (iso + 30, 1.0), (3071, 1.0)):
                colour.AddRGBPoint(h, *mucosa)
                opacity.AddPoint(h, a)
        prop = vtk.vtkVolumeProperty()
        prop.SetColor(colour)
        prop.SetScalarOpacity(opacity)
        prop.SetScalarOpacityUnitDistance(1.0)  # opacity per mm, as our transfer functions
        prop.SetInterpolationTypeToLinear()
        prop.ShadeOn()
        prop.SetAmbient(0.10)
        prop.SetDiffuse(0.90)
        prop.SetSpecular(0.20)
        prop.SetSpecularPower(20.0)
        volume = vtk.vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(prop)
        renderer.AddVolume(volume)
        start = time.perf_counter()
        window.Render()
        first = time.perf_counter() - start
        times = []
        for _ in range(task["runs"]):
            volume.Modified()
            start = time.perf_counter()
            window.Render()
            times.append(time.perf_counter() - start)
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.ReadFrontBufferOff()
        grab.Update()
        out = grab.GetOutput()
        rgb = numpy_support.vtk_to_numpy(out.GetPointData().GetScalars()).reshape(height, width, -1)[::-1, :, :3]
        # VTK blends in linear values and writes them as they are; ours ends with a 2.2 gamma.
        # The same gamma is applied here, outside the timed renders, so the images compare.
        linear = rgb.astype(np.float64) / 255.0
        write_png(task["png"], linear ** (1.0 / 2.2))
        renderer.RemoveVolume(volume)
        results.append({"first_s": first, "times_ms": [1000.0 * t for t in times]})
    json.dump({"vtk_version": vtk.vtkVersion.GetVTKVersion(), "results": results}, open(job["result"], "w"))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__.split("\n\n")[1].split("\n")[0])
    vtk_worker(sys.argv[1])
