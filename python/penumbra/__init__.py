"""Penumbra: hybrid selective ray-traced shadows, from Python.

    import penumbra
    s = penumbra.Scene("builtin:courtyard")
    r = penumbra.Renderer(s, res=(512, 512), light_size=0.1, spp=16)
    f = r.render("srt")            # f.visibility (H x W float32), f.image (H x W x 4 uint8), f.pip, f.stats
    m = r.compare(["sm", "srt"])   # metrics.json's object: every method judged against the Embree reference

Options are the command line's (`penumbra render --help`, docs/options.md): `light_size=0.1` is
`--light-size 0.1`, `res=(512, 512)` is `--res 512x512`, a list is comma-separated, True/False are
on/off. Bad input raises penumbra.Error (a ValueError) with the command line's message.
"""
import json
import struct
import zlib

from ._penumbra import Error, Scene
from ._penumbra import Renderer as _Renderer

__all__ = ["Error", "Scene", "Renderer", "Frame", "compare"]


def _options(options):
    out = []
    for key, value in options.items():
        if value is None:
            continue
        name = "--" + key.replace("_", "-")
        if key == "res" and isinstance(value, (tuple, list)):
            value = f"{value[0]}x{value[1]}"
        elif isinstance(value, bool):
            value = "on" if value else "off"
        elif isinstance(value, (tuple, list)):
            value = ",".join(str(v) for v in value)
        out.append((name, str(value)))
    return out


def _png(rgba):
    """PNG bytes of an H x W x 4 uint8 array (no dependency beyond zlib)."""
    h, w = rgba.shape[0], rgba.shape[1]
    raw = b"".join(b"\0" + rgba[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


class Frame:
    """One rendered frame: visibility (1 = lit), the shaded image, covered pixels, PIP flags of
    methods that classify (None otherwise) and stats (metrics.json's entry of the method)."""

    def __init__(self, d):
        self.width, self.height = d["width"], d["height"]
        self.visibility, self.image, self.covered, self.pip = d["visibility"], d["image"], d["covered"], d["pip"]
        self.stats = json.loads(d["stats"])

    def _repr_png_(self):
        return _png(self.image)

    def __repr__(self):
        return f"<penumbra.Frame {self.stats.get('method')} {self.width}x{self.height} {self.stats['time_ms']['total']:.1f} ms>"


class Renderer:
    """A renderer of one scene with the command line's options (keyword arguments)."""

    def __init__(self, scene, **options):
        if isinstance(scene, str):
            scene = Scene(scene)
        self.scene = scene
        self._r = _Renderer(scene, _options(options))

    def render(self, method):
        return Frame(self._r.render(method))

    def compare(self, methods):
        return json.loads(self._r.compare(list(methods)))

    @property
    def camera(self):
        return self._r.camera

    @camera.setter
    def camera(self, value):
        self._r.camera = value

    @property
    def light(self):
        return self._r.light

    @light.setter
    def light(self, value):
        self._r.light = value

    def settings(self):
        return json.loads(self._r.settings())


def compare(scene, methods, **options):
    """metrics.json's object for `methods` on `scene`, each judged against the Embree reference."""
    return Renderer(scene, **options).compare(methods)
