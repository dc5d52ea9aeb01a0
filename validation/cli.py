"""Command-line interface of the validation package."""

from __future__ import annotations

import argparse

from validation.surfaces import surface_statistics, wm_surface


def _report(args: argparse.Namespace) -> int:
    # Default scene surface (paper, Section 4): D = 2.05 and 2.95, gamma 1.5, M 10, n_max 8.
    n = 256
    for D in (2.05, 2.95):
        heights = wm_surface(n, D=D, rms_slope=0.1, seed=0)
        stats = surface_statistics(heights, 1.0 / n)
        print(f"WM surface D={D}: n={n}, rms height={stats.rms_height:.4g} L, "
              f"rms gradient={stats.rms_gradient:.4g}, rms curvature={stats.rms_curvature:.4g}/L, "
              f"Nayak parameter={stats.nayak:.4g}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m validation")
    sub = parser.add_subparsers(dest="command", required=True)
    report = sub.add_parser("report", help="run the validation report")
    report.set_defaults(handler=_report)
    args = parser.parse_args(argv)
    return args.handler(args)
