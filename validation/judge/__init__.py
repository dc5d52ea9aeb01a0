"""Judging results: errors against the boundary-element reference (:mod:`~validation.judge.compare`),
statistical verdicts (:mod:`~validation.judge.verdicts`) and the paper's findings checked on them;
where verdicts stay undecided, more realizations and a finer reference asked of the run
(:mod:`~validation.judge.decide`, with :func:`~validation.judge.decide.run_scenes`)."""
