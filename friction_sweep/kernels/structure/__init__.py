"""The exact event-driven engine for structures of n masses and m friction contacts (docs: DESIGN §7).

Between events every contact is slipping (a constant force), stuck (a Jenkins spring, or a rigid
constraint on its relative velocity) or without friction, so the motion is linear with constant and
harmonic forcing: in the augmented state z = (x, x', p, cos wt, sin wt, 1) (p: the Jenkins sliders)
it is z' = A z and z(t) = exp(A t) z(0), exact for every mode (flow.py). Events are linear functionals
of z, found without missing a root (roots.py); one period of the motion, with its monodromy and its
measurement, is period.py; the steady state (march, Newton shooting, period-k orbits) is steady.py; an
orbit's time histories are history.py, its exact harmonics harmonics.py (each step's Fourier integrals in
closed form: fourier.py).
Every size is carried by the arrays, so one compilation serves every n and m.
"""
