"""What a TOML case file asks for, end to end: solve, write the results, export and render (``[output]``)."""

from __future__ import annotations

from pathlib import Path

from .casefile import OutputSettings, load_case
from .export import render_response, write_response
from .run import solve, write_results

__all__ = ["run_case_file", "files_of"]


def files_of(f) -> dict:
    """The files of a :class:`~plbar.io.vtk.ResponseFiles` or :class:`~plbar.visuals.render.RenderFiles` by kind."""
    d = {}
    for k in ("pvd", "xdmf", "h5", "steps_csv", "info_json", "montage", "spacetime", "gif"):
        v = getattr(f, k, None)
        if v is not None:
            d[k] = str(v)
    for k in ("vtus", "snapshots"):
        if getattr(f, k, None):
            d[k] = [str(x) for x in getattr(f, k)]
    return d


def run_case_file(path, out=None, overwrite: bool = False, progress: bool = False, loaded=None) -> dict:
    """Do everything a case file asks: solve, write results, and the ``[output]`` extras.

    Parameters
    ----------
    path : path
        The TOML case file.
    loaded : (Case, OutputSettings), optional
        The file as already read by :func:`load_case` (it is then not read again).
    out : path, optional
        Output folder (default: the file's ``[output] dir``, else ``plbar-out``).
    overwrite : bool
        Replace results of another case in ``out``.

    Returns
    -------
    dict
        ``result`` (:class:`plbar.Result`), ``files`` (name -> path or list of paths).
    """
    case, st = loaded if loaded is not None else load_case(path)
    out = Path(out or st.dir or "plbar-out")
    res = solve(case, progress=progress)
    files = {k: str(v) for k, v in write_results(res, out, overwrite=overwrite or st.overwrite).items()}
    files.update(_extras(res, st, out))
    return {"result": res, "files": files}


def _extras(res, st: OutputSettings, out: Path) -> dict:
    """The ``[output]`` extras: the ParaView time series and the pictures of one response."""
    files = {}
    if res.branches and st.vtk:
        files.update(files_of(write_response(res, out / "vtk", branch=st.branch, index=st.index,
                                             periods=st.periods, steps=st.steps, format=st.format)))
    if res.branches and st.render:
        src = out / "vtk" / "response.pvd" if st.vtk and st.format in ("pvd", "both") else res
        files.update({f"render_{k}": v for k, v in files_of(
            render_response(src, out / "render", field=st.field, snapshots=st.snapshots, gif=st.gif,
                            branch=st.branch, index=st.index, steps=st.steps, case=res.case)).items()})
    return files
