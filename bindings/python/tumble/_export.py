"""Writing a run's frames to a file through the C library's writer (include/tumble/writer.h):
CSV with numbers that read back exactly, NumPy .npz, animated glTF 2.0 (.glb/.gltf) with the
scene's shapes, USD text (.usda). The frames written are the ones in memory, bit for bit (tb_writer_frame_values);
the scene is loaded again only for its body names and shapes, which the writer draws from the scene
(a mesh with its own triangles). docs/export.md has the formats."""

import ctypes

import numpy as np

FORMATS = ("csv", "npz", "glb", "gltf", "usda")
ROTATIONS = ("cubic", "linear")


class WriterDef(ctypes.Structure):
    _fields_ = [
        ("format", ctypes.c_int),
        ("rotation_keys", ctypes.c_int),
        ("scene_file", ctypes.c_char_p),  # deprecated and ignored by the library
        ("scene_text", ctypes.c_char_p),  # deprecated and ignored by the library
        ("base_directory", ctypes.c_char_p),  # deprecated and ignored by the library
        ("frame_count", ctypes.c_size_t),
        ("fps", ctypes.c_double),
        ("sample_tolerance", ctypes.c_double),
        ("internal_cookie", ctypes.c_int),
    ]


def declare(lib, error_type):
    """The writer's functions on the library handle (called once, at import)."""
    double_p = ctypes.POINTER(ctypes.c_double)
    signatures = {
        "tb_writer_def_default": (WriterDef, []),
        "tb_output_format_from_name": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_int)]),
        "tb_writer_open": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(WriterDef),
                                          ctypes.c_void_p, ctypes.POINTER(ctypes.c_void_p),
                                          ctypes.POINTER(error_type)]),
        "tb_writer_frame_values": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_double, double_p]),
        "tb_writer_detail": (ctypes.c_char_p, [ctypes.c_void_p]),
        "tb_writer_close": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(error_type)]),
        "tb_writer_destroy": (None, [ctypes.c_void_p]),
    }
    for name, (restype, argtypes) in signatures.items():
        function = getattr(lib, name)
        function.restype = restype
        function.argtypes = argtypes


def format_of(path, format):
    """The format asked for, or the one path's extension names."""
    if format is None:
        extension = str(path).rsplit(".", 1)[-1].lower() if "." in str(path) else ""
        if extension not in FORMATS:
            raise ValueError(f"cannot tell the format from {str(path)!r}: give format= one of "
                             f"{', '.join(FORMATS)}")
        return extension
    if not isinstance(format, str) or format.lower() not in FORMATS:
        raise ValueError(f"format must be one of {', '.join(FORMATS)}, got {format!r}")
    return format.lower()


def write(lib, error_type, fail, frames, scene_handle, path, format=None, rotation="cubic"):
    """Writes frames (tumble.Frames) to path; scene_handle is a loaded scene with the same
    bodies, whose shapes and visual meshes are drawn. fail(status, message) makes the exception
    to raise."""
    if rotation not in ROTATIONS:
        raise ValueError(f"rotation must be one of {', '.join(ROTATIONS)}, got {rotation!r}")
    definition = lib.tb_writer_def_default()
    code = ctypes.c_int()
    lib.tb_output_format_from_name(format_of(path, format).encode(), ctypes.byref(code))
    definition.format = code.value
    definition.rotation_keys = ROTATIONS.index(rotation)
    definition.frame_count = len(frames.t)  # npz: streamed to the file as the frames are given
    definition.fps = 0.0  # USD: time codes per second from the frames' interval
    writer, error = ctypes.c_void_p(), error_type()
    status = lib.tb_writer_open(str(path).encode(), ctypes.byref(definition), scene_handle,
                                ctypes.byref(writer), ctypes.byref(error))
    if status != 0:
        raise fail(status, error.message.decode())
    values = np.ascontiguousarray(np.concatenate(
        [frames.position, frames.orientation, frames.velocity, frames.angular_velocity],
        axis=2), dtype=np.float64)
    double_p = ctypes.POINTER(ctypes.c_double)
    for k in range(len(frames.t)):
        status = lib.tb_writer_frame_values(writer, float(frames.t[k]),
                                            values[k].ctypes.data_as(double_p))
        if status != 0:
            message = lib.tb_writer_detail(writer).decode()
            lib.tb_writer_destroy(writer)
            raise fail(status, f"frame {k}: {message}")
    status = lib.tb_writer_close(writer, ctypes.byref(error))
    if status != 0:
        raise fail(status, error.message.decode())
