"""The README's picture: the quickstart's final particle map, cut at y = 0, coloured by the residual density change.

    make run
    xvfb-run -a pvbatch examples/figures/quickstart/render.py out/quickstart/maps/particles_00035900.vtu \
        examples/figures/quickstart/quickstart.png

pvbatch comes with Debian's paraview and python3-paraview packages (python3-paraview conflicts with
libvtk9-dev, which building vitrum needs: render on another machine or remove it again afterwards). The
committed PNG is this rendering cropped to its content and reduced to 256 colours (PIL, when importable).
"""
import sys

from paraview.simple import (Clip, ColorBy, GetActiveViewOrCreate, GetColorTransferFunction, GetScalarBar, Glyph,
                             Render, SaveScreenshot, Show, XMLUnstructuredGridReader)

vtu, png = sys.argv[1], sys.argv[2]
reader = XMLUnstructuredGridReader(FileName=[vtu])
clip = Clip(Input=reader)  # keep the particles behind the plane y = 0, whole (no cut spheres)
clip.ClipType = "Plane"
clip.ClipType.Origin = [0, 0, 0]
clip.ClipType.Normal = [0, -1, 0]
clip.Crinkleclip = 1
glyphs = Glyph(Input=clip, GlyphType="Sphere")
glyphs.ScaleArray = ["POINTS", "radius"]
glyphs.ScaleFactor = 2.0  # the sphere source has diameter 1
glyphs.GlyphMode = "All Points"
glyphs.GlyphType.ThetaResolution = 16
glyphs.GlyphType.PhiResolution = 12
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [900, 500]
view.Background = [1, 1, 1]
view.UseColorPaletteForBackground = 0
view.OrientationAxesVisibility = 0
display = Show(glyphs, view)
ColorBy(display, ("POINTS", "density_change"))
lut = GetColorTransferFunction("density_change")
lut.ApplyPreset("Inferno (matplotlib)", True)
lut.InvertTransferFunction()
lut.RescaleTransferFunction(0.0, 0.03)
bar = GetScalarBar(lut, view)
bar.Title = "residual density change"
bar.ComponentTitle = ""
bar.TitleColor = [0, 0, 0]
bar.LabelColor = [0, 0, 0]
bar.RangeLabelFormat = "%.2f"
bar.WindowLocation = "Any Location"
bar.Position = [0.88, 0.15]
bar.ScalarBarLength = 0.7
display.SetScalarBarVisibility(view, True)
view.CameraPosition = [3.0, -12.5, 4.0]
view.CameraFocalPoint = [0.0, 0.0, -2.0]
view.CameraViewUp = [0, 0, 1]
view.CameraViewAngle = 30
Render(view)
SaveScreenshot(png, view, ImageResolution=[900, 500], TransparentBackground=0)
try:
    from PIL import Image, ImageChops
except ImportError:
    sys.exit(0)
image = Image.open(png).convert("RGB")
x0, y0, x1, y1 = ImageChops.difference(image, Image.new("RGB", image.size, (255, 255, 255))).getbbox()
image = image.crop((max(0, x0 - 15), max(0, y0 - 15), min(image.width, x1 + 10), min(image.height, y1 + 15)))
image.quantize(colors=256, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE).save(png, optimize=True)
