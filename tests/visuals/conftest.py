import pytest


@pytest.fixture
def keep_figures(monkeypatch, tmp_path):
    """``keep_figures(module)``: the figures ``module`` draws are kept in the returned list (not written) and closed
    after the test."""
    got = []

    def patch(module):
        def keep(fig, out, name):
            got.append(fig)
            return [tmp_path / f"{name}.png"]

        monkeypatch.setattr(module, "_save", keep)
        return got

    yield patch
    import matplotlib.pyplot as plt

    for f in got:
        plt.close(f)
