"""Judging results: errors against the boundary-element reference (:mod:`~validation.judge.compare`),
statistical verdicts (:mod:`~validation.judge.verdicts`) and the paper's findings checked on them."""
