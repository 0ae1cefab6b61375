"""Numerical kernels shared by the core: the math/numpy backend, the Wilson interval, elliptic
integrals and Jacobi functions, quaternions."""
