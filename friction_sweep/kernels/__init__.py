"""numba kernels: pure functions of floats and arrays, status codes instead of exceptions."""
