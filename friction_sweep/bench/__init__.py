"""Benchmarks that users read: work-precision of every method and setting."""
