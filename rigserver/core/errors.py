"""The model library's exceptions.

::

    ValueError
     └── ModelInputError        an argument outside the model's domain (name, value, limit)
          └── ModelUndefinedError   the inputs are valid but the formula has no meaning there
                                    (e.g. k_f^n of (2.1) when σ_T ≤ 2f·HB)

Numerical non-convergence is not an exception: solvers report it in their result.
"""

from __future__ import annotations


class ModelInputError(ValueError):
    """An argument is outside the domain of a model; the message names it and the limit."""


class ModelUndefinedError(ModelInputError):
    """The formula is undefined for these (individually valid) inputs."""
