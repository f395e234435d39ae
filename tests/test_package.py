"""Package-level promises: import cost, the command entry point."""
import subprocess
import sys


def test_core_modules_do_not_import_matplotlib():
    # only fricctl.figures and the CLI plot; python-control (fricctl.design) imports matplotlib
    # itself on import, so it is not in this list
    code = ("import sys, fricctl, fricctl.simulate, fricctl.bench.experiments, fricctl.nn, fricctl.identify, "
            "fricctl.diagnose, fricctl.datasets, fricctl.estimation; "
            "print('matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_python_dash_m_runs_the_cli():
    out = subprocess.run([sys.executable, "-m", "fricctl", "--version"], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.startswith("fricctl ")
    out = subprocess.run([sys.executable, "-m", "fricctl", "design", "pd", "--rise-time", "-1",
                          "--damping", "0.5"], capture_output=True, text=True)
    assert out.returncode == 2 and out.stderr.count("\n") == 1 and "rise_time" in out.stderr
