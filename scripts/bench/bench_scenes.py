"""The benchmark scenes' cameras for the Python benchmark scripts, read from
scripts/bench/bench_scenes.sh, where the shell scripts read them too: one place for every camera
of the benchmark pages (docs/benchmarks/).
"""
import os
import subprocess

SCENES_SH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bench_scenes.sh")


def camera_options(name):
    """The cvc options of the bash array `name` in bench_scenes.sh (e.g. yardstick_camera,
    ct_camera), as a list of strings."""
    result = subprocess.run(["bash", "-c", f'source "{SCENES_SH}" && printf "%s\\n" "${{{name}[@]}}"'],
                            capture_output=True, text=True, check=True)
    options = result.stdout.split()
    if not options:
        raise ValueError(f"{SCENES_SH} has no array {name}")
    return options
