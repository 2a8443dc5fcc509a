"""``kbm diagram``'s averaged curves say why there are none (issue 35, "numerics that find
nothing say so"): the energy-balance averaging needs a confining potential, and a model
whose conservative force does not confine gets the reason in ``averaged_note`` instead of
an empty note."""

from __future__ import annotations

from kbm.model.user_model import custom_model
from numerics.bifurcation.averaged import energy_balance_curves


def test_a_potential_that_does_not_confine_is_named():
    """x'' + x = mu((nu - x^2) x' + c x^3): G(x) = (1 - mu c) x^2/2 ... - mu c x^4/4 falls to
    -infinity for c > 0, so there is no outer period annulus at any (nu, c) of the plane
    (split_conservative's NotConfiningError), and the note says so."""
    model = custom_model("(nu - x**2)*xdot + c*x**3")
    curves, note = energy_balance_curves(model, {"mu": 0.2}, ("nu", "c"),
                                         {"nu": (-0.4, 0.5), "c": (0.1, 1.0)}, n=3)
    assert curves == []
    assert note.startswith("no conservative split at nu = -0.4")
    assert "does not confine" in note


def test_a_confining_plane_has_its_curves_and_no_note():
    """The generalised Hopf (Bautin) family x'' + x = mu (nu + b x^2 - x^4) x': the
    first-order averaged amplitude equation a' = (mu a/2)(nu + b a^2/4 - a^4/8) has its
    Hopf point at nu = 0 and its fold of cycles where the quadratic in a^2 has a double
    root, nu = -b^2/8 (closed form).  The curves are found, on those lines, and the note is
    empty."""
    model = custom_model("(nu + b*x**2 - x**4)*xdot")
    curves, note = energy_balance_curves(model, {"mu": 0.2}, ("b", "nu"),
                                         {"b": (0.2, 1.0), "nu": (-0.2, 0.1)}, n=5)
    assert note == ""
    kinds = {c.kind: c.points for c in curves}
    assert set(kinds) == {"fold", "hopf"}
    for b, nu in kinds["fold"]:
        assert abs(nu + b * b / 8) < 1e-5
    for b, nu in kinds["hopf"]:
        assert abs(nu) < 1e-5
