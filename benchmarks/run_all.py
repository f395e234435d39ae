"""Run every benchmark script in this folder, one after the other."""
import pathlib
import runpy
import sys

here = pathlib.Path(__file__).parent
for script in sorted(here.glob("bench_*.py")):
    if len(sys.argv) > 1 and not any(a in script.name for a in sys.argv[1:]):
        continue
    print(f"\n===== {script.name} =====", flush=True)
    runpy.run_path(str(script), run_name="__main__")
