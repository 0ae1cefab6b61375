"""Numerical kernels shared by the core: the math/numpy backend, the Wilson interval, the root
finders, minimizer and bisection, the Gauss-Legendre rule, elliptic integrals and Jacobi
functions, quaternions."""
