"""Arithmetic whose result does not depend on the processor or on where the numbers sit in
memory: the same bits for one robot alone and for the same robot in a batch, on any x86-64.

numpy picks its kernels by the processor's features (``__cpu_dispatch__``) and by an array's
layout and alignment. Elementwise ``+``, ``-``, ``*``, ``/`` and ``sqrt`` are exact per element
(IEEE 754 rounds each result once), whatever the kernel. Two things are not:

* a float reduction (``@``, ``dot``, ``einsum``, ``sum`` over a strided or batched view): its
  order of additions follows the kernel (BLAS's gemv or gemm, fused multiply-adds, a pairwise
  or a running sum), so the last bit can differ between a batch and one of its rows and between
  processors. :func:`weighted_sums` adds in one fixed order with elementwise operations;
* numpy's own transcendental kernels (``tanh``, ``exp``, ``log``, ``cos``, ``sin``,
  ``arctan2``, ... : SVML or numpy's polynomials on AVX2 or AVX-512, the C library below
  them): :func:`libm` applies the C library's function (the one Python's ``math`` calls, and
  numpy with its dispatch limited to the baseline) element by element: in a C++ loop
  (``epuck_vrep_compat._libm``, a module of its own: not the simulator's core) for tanh, exp,
  log, cos, sin and atan2, else through ``math`` itself.
"""
import math

import numpy as np

from epuck_vrep_compat._libm import atan2, cos, exp, log, sin, tanh

# math's function -> a C++ loop over an array calling the same C library function
_LOOPS = {math.tanh: tanh, math.exp: exp, math.log: log, math.cos: cos, math.sin: sin,
          math.atan2: atan2}


def weighted_sums(x, weights) -> np.ndarray:
    """``x @ weights.T`` for x (..., D) and weights (K, D) -> (..., K), added in one fixed
    order whatever the processor and the layout: the D products (elementwise), then halves
    added to halves (the first ``D // 2`` products plus the next ``D // 2``, an odd one out
    added to the first sum) until one is left. Each step is one elementwise operation over the
    whole batch, so the batch stays vectorised and a row's result is its own alone."""
    x = np.asarray(x, dtype=float)
    weights = np.asarray(weights, dtype=float)
    if weights.ndim != 2 or x.shape[-1:] != weights.shape[1:]:
        raise ValueError(f"need x (..., {weights.shape[-1]}) and weights (K, D), got "
                         f"{x.shape} and {weights.shape}")
    terms = x[..., None, :] * weights                       # (..., K, D)
    while terms.shape[-1] > 1:
        n, half = terms.shape[-1], terms.shape[-1] // 2
        folded = terms[..., :half] + terms[..., half:2 * half]
        if n % 2:
            folded[..., :1] += terms[..., n - 1:]
        terms = folded
    return terms[..., 0] if weights.shape[1] else np.zeros(terms.shape[:-1])


def libm(function, *arrays) -> np.ndarray:
    """``function`` (one of ``math``'s: ``math.tanh``, ``math.atan2``, ...) applied element by
    element to the broadcast ``arrays``, as float64 of their broadcast shape."""
    loop = _LOOPS.get(function)
    if loop is not None:
        if len(arrays) == 1:
            return loop(np.asarray(arrays[0], dtype=float))
        return loop(*(np.ascontiguousarray(a) for a in
                      np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in arrays))))
    if len(arrays) == 1:
        a = np.asarray(arrays[0], dtype=float)
        return np.fromiter(map(function, a.ravel().tolist()), float, a.size).reshape(a.shape)
    args = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in arrays))
    flat = [a.ravel().tolist() for a in args]
    return np.fromiter(map(function, *flat), float, args[0].size).reshape(args[0].shape)
