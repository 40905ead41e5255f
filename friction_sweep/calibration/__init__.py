"""`fsweep calibrate`: Bayesian calibration of the scene to a rig's measurements (issue 18).

Layers, each a module: spec (the calibration spec), data (the measured rows), priors, model (the forward
model: the method's phase and transmissibility at every row), posterior (priors x a circular likelihood),
fit (stage one: MAP by least squares), sampler (stage two: emcee with its diagnostics), report (ArviZ
InferenceData, tables, figures) and command (the CLI). emcee and ArviZ are the extra `calibrate`.
"""
