# Two entry points: `make demo` (the main job) and `make test`. Each creates the virtual
# environment in .venv if it is missing, installing the pinned versions of constraints.txt.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test check-wheel bench bench-ipc setup clean

demo: $(STAMP)
	$(BIN)/python -m pdsketch_mech.check domains/basis.pddl domains/mechanisms/*.pddl problems/*.pddl
	mkdir -p out
	$(BIN)/python -m pdsketch_mech.plan domains/mechanisms/hook-use.pddl problems/hook-use.pddl \
	    --json out/hook-use.json --render out/hook-use.gif

test: $(STAMP)
	$(BIN)/python -m pytest -q

# The wheel, installed in a fresh environment outside the checkout, plans the Hook problem.
check-wheel: $(STAMP)
	bash .ci/wheel

# A short Table 1: all six tasks, Macro+Sampler, 3 test instances each (reruns resume).
bench: $(STAMP)
	$(BIN)/python -m pdsketch_mech.bench mechanisms --methods macro+sampler --trials 3 --timeout 120 \
	    --out out/bench/table1-short --resume

bench-ipc: $(STAMP)
	$(BIN)/python -m pip install --quiet -c constraints.txt -e '.[bench]' --config-settings editable_mode=compat
	$(BIN)/python -m pdsketch_mech.bench ipc tests/data/ipc --peer pyperplan --timeout 120

setup: $(STAMP)

# An editable install in setuptools' compat mode puts the checkout on sys.path with a plain
# .pth line: the default mode's import hook runs at every interpreter start-up, before any
# Ctrl-C handler can be installed, and costs every command start-up time.
# pybullet and ompl publish wheels for CPython 3.10 and 3.11 only; on another version pip would
# try a long source build that fails, so say so in one line instead (setup.cfg's python_requires).
$(STAMP): setup.cfg setup.py pyproject.toml constraints.txt Makefile
	@$(PYTHON) -c 'import sys; v = sys.version_info[:2]; sys.exit(0 if (3, 10) <= v <= (3, 11) else "make: error: pdsketch_mech needs Python 3.10 or 3.11 (pybullet and ompl have no wheels for %d.%d); run: make setup PYTHON=python3.11" % v)'
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -c constraints.txt -e '.[test]' --config-settings editable_mode=compat
	touch $@

clean:
	rm -rf $(VENV) *.egg-info .pytest_cache .hypothesis build dist
