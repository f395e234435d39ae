"""``fricctl identify RUN.csv``: fit a friction law to a measured record.

Reads a CSV record (header ``t,torque,position[,reference]``, see
:class:`fricctl.datasets.Run`), estimates velocity and acceleration with the chosen
estimator, drops the border samples and the samples at rest, and fits the law by
inverse-dynamics least squares (CasADi + IPOPT).  Prints the estimates with
standard errors in the IDIM-LS layout, or with ``--json`` one object:
``model, units, n_samples, parameters{name: {value, std, unit}}, fit_percent,
relative_error_percent, residual_rms, condition_number, solver_status, estimator``.
A bad CSV prints one line on stderr and exits with code 2.
"""

from __future__ import annotations

import argparse
import json


def register(subparsers) -> None:
    from ..estimation import ESTIMATORS
    from ..identify import MODELS
    from ..units import KINDS

    p = subparsers.add_parser(
        "identify", help="fit a friction law to a measured record (CSV)",
        description=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", metavar="RUN.csv", help="record with header t,torque,position[,reference]")
    p.add_argument("--model", choices=tuple(MODELS), default="coulomb_viscous",
                   help="friction law (default coulomb_viscous: inertia, viscous, Coulomb, offset)")
    p.add_argument("--estimator", choices=tuple(ESTIMATORS), default="butterworth_central",
                   help="velocity/acceleration estimator (default butterworth_central, "
                        "cut-off a fifth of the Nyquist frequency)")
    p.add_argument("--units", choices=KINDS, default=None,
                   help="override the record's '# units:' line")
    p.add_argument("--border", type=int, default=50, metavar="N",
                   help="samples dropped at each end (default 50)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..datasets import Run
    from ..identify import identify_run

    record = Run.from_csv(args.run, units=args.units)
    result = identify_run(record, model=args.model, estimator=args.estimator, border=args.border)
    if args.json:
        out = result.as_dict()
        out["estimator"] = args.estimator
        print(json.dumps(out, indent=2))
    else:
        print(f"{record.source}: {record.n_samples} samples at {record.sample_time:g} s, "
              f"estimator {args.estimator}")
        print(result.report())
    return 0
