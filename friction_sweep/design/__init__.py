"""The damper designer's answers, built on the exact per-point solvers: the resonance peak over
frequency for each friction level (peak.py) and the friction that minimises it (optimum.py)."""
