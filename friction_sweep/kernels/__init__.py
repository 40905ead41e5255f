"""numba kernels: functions of floats, Point records and arrays (results written into caller-owned
arrays), status codes instead of exceptions."""
