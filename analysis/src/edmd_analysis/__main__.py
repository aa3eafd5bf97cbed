"""Command line: ``python -m edmd_analysis report OUT -o REPORT``."""

import argparse
import sys

from .report import report


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m edmd_analysis", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    rep = sub.add_parser("report", help="write every figure of a sweep as PNG, and an index.html")
    rep.add_argument("out", help="sweep output directory (edmd run -o OUT)")
    rep.add_argument("-o", "--output", help="report directory (default OUT/report)")
    rep.add_argument("--max-points", type=int, default=24, help="grid points drawn (default 24)")
    args = parser.parse_args(argv)
    try:
        page = report(args.out, args.output or f"{args.out}/report", args.max_points)
    except (FileNotFoundError, ValueError, KeyError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    print(f"report: {page}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
