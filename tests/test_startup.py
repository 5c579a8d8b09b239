"""Classical planning never loads the simulator or the numeric stack (what keeps `plan` and
`check` starting in ~0.1 s), PyBullet loads without its banner, and `bench startup` runs."""
import json
import os
import subprocess
import sys

from pdsketch_mech.bench import __main__ as bench

from conftest import DATA, ROOT

HEAVY = ("pybullet", "scipy", "torch", "trimesh", "ompl")
BLOCKS = [os.path.join(DATA, "ipc", "blocks", "domain.pddl"), os.path.join(DATA, "ipc", "blocks", "p01.pddl")]


def loaded_heavy_modules(code: str):
    """The heavy top-level packages in sys.modules after running `code` in a fresh interpreter."""
    script = f"import sys\n{code}\nprint(sorted({{m.split('.')[0] for m in sys.modules}} & {set(HEAVY)!r}))"
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=ROOT, check=True)
    return done.stdout.strip().splitlines()[-1]


def test_importing_plan_and_check_loads_nothing_heavy():
    assert loaded_heavy_modules("import pdsketch_mech.commands.plan, pdsketch_mech.commands.check") == "[]"


def test_checking_and_planning_classical_files_loads_nothing_heavy():
    code = (f"from pdsketch_mech.commands import check, plan\n"
            f"assert check.main({BLOCKS!r}) == 0 and plan.main({BLOCKS!r}) == 0")
    assert loaded_heavy_modules(code) == "[]"


def test_in_a_command_pybullet_loads_without_its_banner_from_any_module():
    code = ("import sys\nsys.orig_argv = [sys.executable, '-m', 'pdsketch_mech.plan']\n"
            "import pdsketch_mech, pybullet; pybullet.connect(pybullet.DIRECT)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert (done.stdout, done.stderr) == ("", "")


def test_importing_the_package_changes_nothing_in_a_library_process():
    """No Ctrl-C handler, no import hook, no environment variable: those belong to commands."""
    code = ("import os, signal, sys\n"
            "before = (signal.getsignal(signal.SIGINT), list(sys.meta_path), dict(os.environ))\n"
            "import pdsketch_mech, pdsketch_mech.api\n"
            "print(before == (signal.getsignal(signal.SIGINT), list(sys.meta_path), dict(os.environ)))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert done.stdout.strip().splitlines()[-1] == "True"


def test_bench_startup_reports_every_case(tmp_path, capsys):
    out = tmp_path / "startup.json"
    assert bench.main(["startup", "--runs", "1", "--json", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("startup: median of 1 fresh processes") and len(lines) == 5
    figures = json.loads(out.read_text())
    assert [c["target_s"] for c in figures["cases"]] == [0.3, 0.3, 0.3, None]
    assert all(c["median_s"] > 0 for c in figures["cases"])


def test_a_command_gives_numpy_one_blas_thread_unless_the_user_chose():
    """`python -m pdsketch_mech.X` sets OPENBLAS_NUM_THREADS=1 before numpy is imported
    (process.limit_blas_threads: BLAS threads spin against a benchmark's other plan), and
    leaves a value the user set alone; a library user's process is not touched."""
    def threads(orig_argv, env_value):
        script = (f"import sys\nsys.orig_argv = {orig_argv!r}\nimport os, pdsketch_mech\n"
                  f"assert 'numpy' not in sys.modules\nprint(os.environ.get('OPENBLAS_NUM_THREADS'))")
        env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
        if env_value is not None:
            env["OPENBLAS_NUM_THREADS"] = env_value
        done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=ROOT, env=env, check=True)
        return done.stdout.strip()
    command = [sys.executable, "-m", "pdsketch_mech.plan"]
    assert threads(command, None) == "1"
    assert threads(command, "2") == "2"
    assert threads([sys.executable, "-c", "pass"], None) == "None"
