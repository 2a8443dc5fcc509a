"""The installed distribution's version (``kbm.__version__``, read on first use: the
package metadata costs an import that ``import kbm`` does not need)."""

from importlib.metadata import PackageNotFoundError, version as _version

try:  # the version lives in pyproject.toml only
    __version__ = _version("kbm")
except PackageNotFoundError:  # pragma: no cover - running from a tree that is not installed
    __version__ = "0+unknown"
