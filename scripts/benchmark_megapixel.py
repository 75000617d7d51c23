#!/usr/bin/python3
"""Runs the megapixel benchmark (native/bench/bench_megapixel.cpp) and prints a Markdown table of the
median seconds of the default call, our graph cut alone and the reference alpha-expansion per size,
with the reference's ratios to both, and the machine, date and command it was measured with.

    /usr/bin/python3 scripts/benchmark_megapixel.py --repetitions 3 --sizes 512 1024
"""

import argparse
import datetime
import json
import os
import re
import resource
import shlex
import statistics
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
VARIANTS = ("default_call", "graph_cut", "reference_expansion")
RUN_NAME = re.compile(r"^BM_Megapixel/(\w+)/(\d+)/")
SECONDS_PER_UNIT = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", type=Path, default=REPO / "build" / "native" / "shadecut_bench",
                        help="the shadecut_bench executable (default: %(default)s)")
    parser.add_argument("--repetitions", type=int, default=3, help="runs per benchmark (default: %(default)s)")
    parser.add_argument("--sizes", type=int, nargs="+", default=[512, 1024, 2048],
                        help="image sizes (default: %(default)s)")
    parser.add_argument("--reference-sizes", type=int, nargs="*", default=[512, 1024],
                        help="sizes at which the reference expansion runs too (default: %(default)s; it took "
                             "586 s at 1024 px and grows about 9 times per doubling, so 2048 px takes over an hour)")
    parser.add_argument("--reference-repetitions", type=int, default=1,
                        help="runs of the reference expansion per size (default: %(default)s)")
    parser.add_argument("--memory-size", type=int, default=2048,
                        help="size of the default call whose peak memory is measured, alone in its process "
                             "(default: %(default)s; 0 = none)")
    return parser.parse_args()


def alternatives(sizes):
    return "(" + "|".join(str(size) for size in sizes) + ")"


def benchmark_commands(arguments):
    """Ours, then the reference, which runs for minutes per size and so gets its own repetitions."""
    commands = [[str(arguments.binary),
                 f"--benchmark_filter=^BM_Megapixel/(default_call|graph_cut)/{alternatives(arguments.sizes)}/",
                 f"--benchmark_repetitions={arguments.repetitions}", "--benchmark_format=json"]]
    if arguments.reference_sizes:
        commands.append([str(arguments.binary),
                         f"--benchmark_filter=^BM_Megapixel/reference_expansion/{alternatives(arguments.reference_sizes)}/",
                         f"--benchmark_repetitions={arguments.reference_repetitions}", "--benchmark_format=json"])
    return commands


def peak_bytes_per_pixel(arguments):
    """Peak resident memory of a process that renders the test scene and runs one default call, per
    pixel of the call: an upper bound of the call's own, since it includes the scene's arrays. Run
    before anything else, because the kernel reports the largest peak of any child so far."""
    command = [str(arguments.binary), f"--benchmark_filter=^BM_Megapixel/default_call/{arguments.memory_size}/",
               "--benchmark_format=json"]
    subprocess.run(command, stdout=subprocess.DEVNULL, check=True)
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024  # Linux reports KiB
    return peak, peak / arguments.memory_size ** 2, command


def median_seconds(report):
    """{(variant, size): median seconds} over the repetitions; the aggregates Google Benchmark adds
    are skipped so that one repetition and many are read alike."""
    samples = {}
    for run in report["benchmarks"]:
        if run.get("run_type", "iteration") != "iteration":
            continue
        match = RUN_NAME.match(run["run_name"] if "run_name" in run else run["name"])
        if not match:
            continue
        seconds = run["real_time"] * SECONDS_PER_UNIT[run["time_unit"]]
        samples.setdefault((match.group(1), int(match.group(2))), []).append(seconds)
    return {key: statistics.median(values) for key, values in samples.items()}


def cpu_model():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def format_seconds(seconds):
    return "–" if seconds is None else f"{seconds:.3f}"


def format_ratio(numerator, denominator):
    return "–" if numerator is None or denominator is None else f"{numerator / denominator:.1f}×"


def markdown_table(medians):
    lines = ["| size (px) | default call (s) | graph cut alone (s) | reference expansion (s) "
             "| reference / default | reference / graph cut |",
             "|---:|---:|---:|---:|---:|---:|"]
    for size in sorted({size for _, size in medians}):
        default_call, graph_cut, reference = (medians.get((variant, size)) for variant in VARIANTS)
        lines.append(f"| {size} | {format_seconds(default_call)} | {format_seconds(graph_cut)} "
                     f"| {format_seconds(reference)} | {format_ratio(reference, default_call)} "
                     f"| {format_ratio(reference, graph_cut)} |")
    return "\n".join(lines)


def main():
    arguments = parse_arguments()
    if not arguments.binary.is_file() or not os.access(arguments.binary, os.X_OK):
        sys.exit(f"error: benchmark binary {arguments.binary} not found or not executable; build it with "
                 "-DSHADECUT_BUILD_BENCHMARKS=ON (target shadecut_bench) or pass --binary")
    if arguments.repetitions < 1 or arguments.reference_repetitions < 1:
        sys.exit("error: --repetitions and --reference-repetitions must be at least 1")
    memory = peak_bytes_per_pixel(arguments) if arguments.memory_size else None
    medians = {}
    commands = benchmark_commands(arguments)
    for command in commands:
        # The benchmark's own progress goes to stderr and is left on the terminal.
        finished = subprocess.run(command, stdout=subprocess.PIPE, text=True)
        if finished.returncode != 0:
            sys.exit(f"error: {shlex.join(command)} exited with status {finished.returncode}")
        medians.update(median_seconds(json.loads(finished.stdout)))
    if not medians:
        sys.exit("error: the benchmark reported no BM_Megapixel run; check --sizes")
    print(markdown_table(medians))
    print()
    print(f"Machine: {len(os.sched_getaffinity(0))} cores (nproc), {cpu_model()}; "
          f"date: {datetime.datetime.now().astimezone().isoformat(timespec='seconds')}; medians of")
    for command in commands:
        print(f"- `{shlex.join(command)}`")
    if memory:
        peak, per_pixel, memory_command = memory
        print(f"Peak memory of the default call at {arguments.memory_size} px, scene included: {peak / 2**20:.0f} MiB, "
              f"{per_pixel:.0f} bytes per pixel (`{shlex.join(memory_command)}`, alone in its process)")


if __name__ == "__main__":
    main()
