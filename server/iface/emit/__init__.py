"""Emitters: from one compiled interface, the files a framework needs.

A target is a small descriptor (``Target``) found through the ``iface.targets``
entry point group; its ``generate`` renders jinja2 templates over the model and
returns files instead of writing them, so that generation can be previewed,
checked or written atomically by ``write.write_files``.

Emitters read the model only. May import: ``model``, ``syntax``, ``semantics``, ``text``, ``forms``.
"""

from __future__ import annotations

from .base import GeneratedFile, GenerationError, Result, Target, TemplateSet
from .registry import generate, get_target, targets

__all__ = ["GeneratedFile", "GenerationError", "Result", "Target", "TemplateSet", "generate",
           "get_target", "targets"]
