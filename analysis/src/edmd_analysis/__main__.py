"""Command line: ``python -m edmd_analysis report OUT [-o REPORT]`` (every figure of a sweep and an
index.html) and ``python -m edmd_analysis movie OUT [--replica K] [-o FILE]`` (an animation of one
replica from its snapshots)."""

import argparse
import sys

from .movie import COLOURINGS, movie
from .report import report


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m edmd_analysis", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    rep = sub.add_parser("report", help="write every figure of a sweep as PNG, and an index.html")
    rep.add_argument("out", help="sweep output directory (edmd run -o OUT)")
    rep.add_argument("-o", "--output", help="report directory (default OUT/report)")
    rep.add_argument("--max-points", type=int, default=24, help="grid points drawn (default 24)")
    rep.add_argument("--no-movies", action="store_true",
                     help="skip the movie of one replica per class")
    rep.add_argument("--jobs", type=int, help="figures drawn at a time, one process each (default: "
                     "one per core)")
    mov = sub.add_parser("movie", help="an animation of one replica from its snapshots (GIF; MP4 "
                         "too when ffmpeg is present)")
    mov.add_argument("out", help="sweep output directory, or one replica file")
    mov.add_argument("--replica", type=int, help="replica index K (default: the finished replica "
                     "with the most snapshots)")
    mov.add_argument("-o", "--output", help="movie file, .gif or .mp4 (default OUT/movies/rK.gif, "
                     "and rK.mp4 when ffmpeg is present)")
    mov.add_argument("--fps", type=float, default=5.0, help="frames per second (default 5)")
    mov.add_argument("--colour", choices=COLOURINGS, help="grain colours (default: species in "
                     "mixtures, spin for rough grains, speed otherwise)")
    arrows = mov.add_mutually_exclusive_group()
    arrows.add_argument("--arrows", dest="arrows", action="store_true", default=None,
                        help="draw velocity arrows (default where the colour is not the speed)")
    arrows.add_argument("--no-arrows", dest="arrows", action="store_false")
    mov.add_argument("--max-frames", type=int, help="at most this many frames, evenly spread")
    mov.add_argument("--size", type=int, default=640, help="frame width in pixels (default 640)")
    mov.add_argument("--dpi", type=int, help="pixels per inch of the 5-inch frame, instead of --size")
    args = parser.parse_args(argv)
    try:
        if args.command == "report":
            page = report(args.out, args.output or f"{args.out}/report", args.max_points,
                          movies=not args.no_movies, jobs=args.jobs)
            print(f"report: {page}")
        else:
            if args.fps <= 0:
                raise ValueError(f"--fps {args.fps:g}: must be positive")
            if args.dpi is not None and args.dpi <= 0:
                raise ValueError(f"--dpi {args.dpi}: must be a positive number of pixels per inch")
            if args.size < 16:
                raise ValueError(f"--size {args.size}: a frame needs at least 16 pixels")
            if args.max_frames is not None and args.max_frames < 2:
                raise ValueError(f"--max-frames {args.max_frames}: a movie needs at least 2")
            for path in movie(args.out, args.replica, args.output, fps=args.fps, colour=args.colour,
                              arrows=args.arrows, dpi=args.dpi, max_frames=args.max_frames,
                              size=args.size):
                print(f"movie: {path}")
    except KeyboardInterrupt:
        print("interrupted: nothing half-written is left under a final name", file=sys.stderr)
        return 130
    except (ValueError, KeyError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    except OSError as e:
        # A read-only or missing output, a file where a directory belongs: one line, no traceback.
        where = f"{e.filename}: " if e.filename else ""
        print(f"error: {where}{e.strerror or e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
