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


# The layers of docs/architecture.md, bottom to top: a module imports only from its own layer
# or below (at any place in the file, lazy imports included).  bench reads the diagnosis's
# cause registry to hide an effect (the diagnosis never imports the bench), so it sits above.
LAYERS = (
    ("_validate", "_cache", "_jit", "_json", "_atomic", "_cnames", "units"),
    ("friction",),
    ("params",),
    ("plant", "netlayout"),
    ("controllers", "compensators", "estimation", "datasets"),
    ("simulate",),
    ("design", "identify", "nn", "data"),
    ("diagnose",),
    ("bench",),
    ("paper",),
    ("compare",),
    ("figures", "cli", "__init__", "__main__", "_readme"),
)


def _package_imports():
    """(importing top-level module, imported top-level module, file) for every package import."""
    import ast
    from pathlib import Path

    import fricctl

    root = Path(fricctl.__file__).resolve().parent
    for f in sorted(root.rglob("*.py")):
        src = f.relative_to(root).parts[0].removesuffix(".py")
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level > 0:
                base = f.parent
                for _ in range(node.level - 1):
                    base = base.parent
                parts = base.joinpath(*(node.module.split(".") if node.module else [])).relative_to(root).parts
                targets = [parts[0]] if parts else [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("fricctl."):
                targets = [node.module.split(".")[1]]
            elif isinstance(node, ast.Import):
                targets = [a.name.split(".")[1] for a in node.names if a.name.startswith("fricctl.")]
            else:
                continue
            for t in targets:
                yield src, t.removesuffix(".py"), f.relative_to(root)


def test_no_module_imports_from_a_layer_above_its_own():
    level = {name: i for i, layer in enumerate(LAYERS) for name in layer}
    seen = set()
    for src, dst, f in _package_imports():
        seen.add(src)
        if dst not in level:  # a name imported from the package root (e.g. __version__)
            continue
        assert level[dst] <= level[src], f"{f} imports fricctl.{dst} from a layer above its own"
    assert seen <= set(level), f"modules missing from LAYERS: {sorted(seen - set(level))}"


def test_the_sampled_loop_loads_no_network_package():
    # the loop evaluates a network through fricctl.netlayout; the network package (trainers,
    # files, C export) sits above it and is not imported with the simulator
    code = ("import sys, fricctl.simulate; "
            "print(sorted(m for m in sys.modules if m.startswith(('fricctl.nn', 'casadi'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
