"""Issues 30 and 31: the structure engine's start state. A point solved from a state (x, v, the Jenkins sliders,
each contact's status at the section) instead of rest, its end state (the steady orbit's at the section), and
what rides on them: the second start where static friction exceeds kinetic, and stepped-sine sweeps.

The truths: an orbit's end state is a fixed point of the period map, so a solve started there settles in its
first period with the same numbers; two steady states at one point are confirmed by the independent hybrid
integrator (tests/independent_structure.py, SciPy's DOP853) from the same two starts.
"""

from __future__ import annotations

import numpy as np

from friction_sweep.structures import ContactDef, StructureDef, assemble, solve_points

#: the issue's blade with an under-platform damper on one rigid contact (benchmarks/structures.py's BLADE)
BLADE = StructureDef("force", {"blade": 1.0, "damper": 0.1}, (("ground", "blade", 1.0), ("blade", "damper", 2.0)),
                     (("ground", "blade", 0.004),), (ContactDef("platform", ("damper", "ground"), 0.3),),
                     {"blade": 1.0})
#: two masses, a Jenkins contact at the root and a rigid one at the tip
JENKINS = StructureDef("force", {"blade": 1.0, "damper": 0.2}, (("ground", "blade", 1.0), ("blade", "damper", 1.0)),
                       (("ground", "blade", 0.03),),
                       (ContactDef("root", ("blade", "ground"), 0.2, 8.0), ContactDef("tip", ("damper", "ground"), 0.1)),
                       {"blade": 1.0})


def test_an_orbit_restarted_from_its_end_state_settles_at_once():
    """The end state is on the steady orbit at the section: from it the first period closes the orbit (the
    march's P(s) = s within steady_tol), and every number agrees with the solve from rest."""
    for d, w in ((BLADE, np.linspace(0.3, 2.8, 12)), (JENKINS, np.linspace(0.4, 2.0, 8))):
        a = assemble(d)
        s = np.ones(w.size)
        rest = solve_points(a, w, s)
        assert (rest["steady_state"] == 0).all()
        again = solve_points(a, w, s, start=rest["end_state"])
        assert (again["steady_state"] == 0).all()
        assert (again["periods"] == 1).all()
        np.testing.assert_allclose(again["amplitude"], rest["amplitude"], rtol=1e-8)
        np.testing.assert_array_equal(again["regime"], rest["regime"])
        np.testing.assert_array_equal(again["stops_per_period"], rest["stops_per_period"])
        np.testing.assert_allclose(again["end_state"], rest["end_state"], rtol=1e-6, atol=1e-9)


def test_a_nan_start_is_rest():
    a = assemble(BLADE)
    w, s = np.array([0.5, 1.2]), np.array([1.0, 1.0])
    rest = solve_points(a, w, s)
    nan = solve_points(a, w, s, start=np.full_like(rest["end_state"], np.nan))
    for name, values in rest.items():
        np.testing.assert_array_equal(nan[name], values, err_msg=name)
