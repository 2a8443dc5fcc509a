"""Shared test configuration: a hypothesis profile without deadlines (sympy timings vary)."""

from hypothesis import HealthCheck, settings

settings.register_profile("kbm", deadline=None, max_examples=25,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("kbm")
