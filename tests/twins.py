"""A kernel module whose helpers Python can call: each numba helper replaced by its twin with a wrapper."""

from plbar.util.jit import python_twin


class Twins:
    """``Twins(module).f`` is :func:`plbar.util.jit.python_twin` of ``module.f`` (anything else as it is)."""

    def __init__(self, module):
        self._module = module

    def __getattr__(self, name):
        return python_twin(getattr(self._module, name))
