"""The survey of the real motion: what the bar does at every forcing period, and the damping of that motion.

* :mod:`.points` -- one chunk of forcing periods simulated together (:mod:`plbar.motion`) and characterised;
* :mod:`.tasks` -- the study's tasks: chunks from rest, and sweeps that carry the state up or down in ``T``;
* :mod:`.settle` -- motions still approaching a stable orbit, told apart from irregular ones;
* :mod:`.loads` -- the survey at every load position or amplitude (and size): :func:`survey_loads`,
  :class:`SurveyLoads` (``axis = AMPLITUDES``: the (T, A) map);
* :mod:`.motion` -- one motion of a survey folder simulated again (export, render): :func:`survey_motion`;
* :mod:`.restitution` -- the survey at every coefficient of restitution ``e`` (Newton's impact law; ``e = 0`` the
  paper's plastic impact, its upper limit): :func:`survey_restitution`, :class:`SurveyRestitution`;
* :mod:`.refine` -- the survey at several sizes N and the convergence of its means
  (:class:`SurveyRefinement`);
* :mod:`.study` -- :func:`survey` (in memory), :func:`run_survey` (a resumable study folder with
  ``survey.csv``, ``summary.json`` and the figure).
"""

from .points import COLUMNS, survey_chunk
from .loads import AMPLITUDES, POSITIONS, SurveyLoads, load_positions, run_survey_loads, survey_loads
from .motion import SurveyMotion, is_survey, survey_motion
from .refine import SurveyRefinement, run_survey_refine
from .restitution import (RESTITUTION_COLUMNS, SurveyRestitution, check_restitutions, survey_restitution,
                          write_restitution)
from .study import Survey, default_periods, default_record, run_survey, survey, survey_study
from .tasks import MODES, case_of

__all__ = ["COLUMNS", "survey_chunk", "Survey", "default_periods", "default_record", "run_survey", "survey",
           "survey_study", "SurveyRefinement", "run_survey_refine", "MODES", "case_of", "SurveyLoads", "load_positions",
           "AMPLITUDES", "POSITIONS",
           "run_survey_loads", "survey_loads", "SurveyMotion", "is_survey", "survey_motion", "RESTITUTION_COLUMNS",
           "SurveyRestitution", "check_restitutions", "survey_restitution", "write_restitution"]
