"""The package's version: it must equal the C library's (tb_version), checked when the library
is loaded (_native.py), and pyproject.toml's."""

__version__ = "0.1.0"
