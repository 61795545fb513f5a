"""Every ctypes mirror of a C API struct (python/mbx/_lib.py) has the header's
layout: the same size and, field by field, the same offsets. The C side is
measured by compiling a small program against mbx/mbx.h and mbx/mbx_files.h
with this machine's C compiler, so a field added to the header but not to
the mirror (or typed differently) fails here rather than corrupting memory
in a user's script."""
import ctypes
import os
import pathlib
import shutil
import subprocess

import pytest

from mbx import _lib

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
INCLUDES = [ROOT / "sdk" / "include", ROOT / "host_adapters" / "files_capi" / "include"]


def mirrors():
    """(ctypes class, C struct name) for every Structure whose docstring names one."""
    out = []
    for name in dir(_lib):
        cls = getattr(_lib, name)
        if isinstance(cls, type) and issubclass(cls, ctypes.Structure) and cls.__doc__:
            c_name = cls.__doc__.split()[0].rstrip(":.,")
            if c_name.startswith("mbx_"):
                out.append((cls, c_name))
    return out


def c_layout(tmp_path, pairs):
    """{struct: (size, {field: offset})} as the C compiler lays them out."""
    lines = ["#include <stddef.h>", "#include <stdio.h>", "#include <mbx/mbx.h>", "#include <mbx/mbx_files.h>",
             "int main(void) {"]
    for cls, c_name in pairs:
        lines.append(f'    printf("{c_name} size %zu\\n", sizeof({c_name}));')
        for field, _ in cls._fields_:
            lines.append(f'    printf("{c_name} {field} %zu\\n", offsetof({c_name}, {field}));')
    lines += ["    return 0;", "}"]
    source = tmp_path / "layout.c"
    source.write_text("\n".join(lines) + "\n")
    compiler = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    if not compiler:
        pytest.fail("no C compiler to measure the header's layout with")
    # The sanitizer runtime preloaded for this interpreter is not for the compiler.
    env = {k: v for k, v in os.environ.items() if k not in ("LD_PRELOAD", "ASAN_OPTIONS", "UBSAN_OPTIONS")}
    exe = tmp_path / "layout"
    subprocess.run([compiler, "-std=c99", *[f"-I{p}" for p in INCLUDES], str(source), "-o", str(exe)], check=True,
                   env=env)
    layout = {}
    for line in subprocess.run([str(exe)], check=True, capture_output=True, text=True, env=env).stdout.splitlines():
        struct, key, value = line.split()
        size, fields = layout.setdefault(struct, (None, {}))
        if key == "size":
            layout[struct] = (int(value), fields)
        else:
            fields[key] = int(value)
    return layout


def test_every_mirror_has_the_headers_size_and_offsets(tmp_path):
    pairs = mirrors()
    # Every Structure of the mirror names its C struct, so none escapes the
    # check (a renamed docstring would make this test check less).
    structures = [c for c in vars(_lib).values()
                  if isinstance(c, type) and issubclass(c, ctypes.Structure) and c.__module__ == _lib.__name__]
    assert sorted(c.__name__ for c, _ in pairs) == sorted(c.__name__ for c in structures)
    assert len(pairs) >= 20
    layout = c_layout(tmp_path, pairs)
    problems = []
    for cls, c_name in pairs:
        size, offsets = layout[c_name]
        if ctypes.sizeof(cls) != size:
            problems.append(f"{cls.__name__} ({c_name}): {ctypes.sizeof(cls)} bytes, the header's {size}")
        for field, _ in cls._fields_:
            mine = getattr(cls, field).offset
            if mine != offsets[field]:
                problems.append(f"{cls.__name__}.{field}: offset {mine}, the header's {offsets[field]}")
    assert not problems, "\n".join(problems)


def test_a_wrong_mirror_is_caught(tmp_path):
    """The check itself: a mirror missing the header's last field is smaller."""
    class Short(ctypes.Structure):
        """mbx_files_error with its message left out."""
        _fields_ = _lib.FilesError._fields_[:-1]
    size, _ = c_layout(tmp_path, [(Short, "mbx_files_error")])["mbx_files_error"]
    assert ctypes.sizeof(Short) != size
