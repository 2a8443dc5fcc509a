"""Independent references used by the tests (never by the package)."""
