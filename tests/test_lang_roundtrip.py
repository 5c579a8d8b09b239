"""parse(write(x)) == x: on the shipped IPC benchmarks, the project's domains, and generated trees."""
import glob
import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pdsketch_mech.lang import nodes as n
from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.lang.parser import KNOWN_REQUIREMENTS, parse_file, parse_text
from pdsketch_mech.lang.writer import write

from conftest import DATA, ROOT

IPC_DOMAINS = ["blocks", "gripper", "logistics00", "depot", "driverlog", "satellite", "zenotravel",
               "rovers", "tpp", "miconic", "ferry"]
PROJECT_FILES = sorted(glob.glob(os.path.join(ROOT, "domains", "**", "*.pddl"), recursive=True)
                       + glob.glob(os.path.join(ROOT, "problems", "*.pddl")))


def ipc_files(domain):
    folder = os.path.join(DATA, "ipc", domain)
    return os.path.join(folder, "domain.pddl"), sorted(
        f for f in glob.glob(os.path.join(folder, "*.pddl")) if not f.endswith("domain.pddl"))


@pytest.mark.parametrize("name", IPC_DOMAINS)
def test_ipc_domain_and_problems_type_check(name):
    domain_file, problem_files = ipc_files(name)
    loaded = load_domain([domain_file])
    assert loaded.domain.actions, "an IPC domain has actions"
    assert problem_files, "every shipped domain has at least one problem"
    for path in problem_files:
        domain, problem = load_problem(path, [loaded])
        assert domain is loaded
        assert problem.init and problem.goal != n.TRUE


@pytest.mark.parametrize("name", IPC_DOMAINS)
def test_ipc_files_round_trip(name):
    domain_file, problem_files = ipc_files(name)
    for path in [domain_file, *problem_files]:
        tree = parse_file(path)
        assert parse_text(write(tree)) == tree, path


@pytest.mark.parametrize("path", PROJECT_FILES, ids=lambda p: os.path.relpath(p, ROOT))
def test_project_files_round_trip(path):
    tree = parse_file(path)
    assert parse_text(write(tree)) == tree


def test_round_trip_detects_a_changed_tree():
    """Equality ignores locations but not content: the property above can fail."""
    tree = parse_file(os.path.join(ROOT, "domains", "basis.pddl"))
    changed = parse_text(write(tree).replace("(holding ?x)", "(holding ?s)", 1))
    assert changed != tree


# ----------------------------------------------------------------------------- generated trees
RESERVED = {"and", "or", "not", "imply", "forall", "exists", "when", "either", "define", "domain", "problem"}
names = st.from_regex(r"[a-z][a-z0-9_\-]{0,7}", fullmatch=True).filter(lambda s: s not in RESERVED)
variables = names.map(lambda s: "?" + s)
terms = st.one_of(variables.map(n.Var), names.map(n.Const))
typed = st.builds(n.TypedName, names, names)
typed_vars = st.builds(n.TypedName, variables, names)
atoms = st.builds(n.Atom, names, st.tuples() | st.lists(terms, max_size=3).map(tuple))
small = lambda s: st.lists(s, max_size=3).map(tuple)  # noqa: E731


def formulas(with_when=False):
    def extend(children):
        options = [
            st.builds(n.And, small(children)), st.builds(n.Or, small(children)),
            st.builds(n.Not, children), st.builds(n.Imply, children, children),
            st.builds(n.Forall, small(typed_vars), children), st.builds(n.Exists, small(typed_vars), children),
        ]
        if with_when:
            options.append(st.builds(n.When, children, children))
        return st.one_of(options)
    return st.recursive(atoms | st.builds(n.Equals, terms, terms), extend, max_leaves=6)


strings = st.text(st.characters(blacklist_characters='"\n\r', blacklist_categories=("Cs", "Cc")), max_size=8)
samplers = st.none() | strings
domains = st.builds(
    n.Domain, names,
    requirements=small(st.sampled_from(sorted(KNOWN_REQUIREMENTS))),
    extends=small(strings),
    types=small(typed), value_types=small(typed), constants=small(typed),
    predicates=small(st.builds(n.Predicate, names, small(typed_vars))),
    actions=small(st.builds(n.Action, names, small(typed_vars), formulas(), formulas(with_when=True))),
    streams=small(st.builds(n.Stream, names, small(typed_vars), formulas(), small(typed_vars), formulas(),
                            samplers)),
    mechanisms=small(st.builds(n.Mechanism, names, small(typed_vars), formulas(), formulas(),
                               small(st.builds(n.ActionCall, names, small(terms))), samplers)),
)
scene_values = st.recursive(
    st.floats(allow_nan=False, allow_infinity=False) | strings | names.map(n.Symbol),
    lambda inner: st.lists(inner, max_size=4).map(tuple), max_leaves=6)
problems = st.builds(
    n.Problem, names, names,
    requirements=small(st.sampled_from(sorted(KNOWN_REQUIREMENTS))),
    objects=small(typed),
    init=small(st.builds(n.Atom, names, small(names.map(n.Const)))),
    goal=formulas(),
    scene=st.none() | small(st.builds(n.SceneEntry, names, small(st.builds(
        n.SceneProp, names.map(lambda s: ":" + s), st.none() | scene_values)))),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(domains)
def test_generated_domains_round_trip(domain):
    assert parse_text(write(domain)) == domain


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(problems)
def test_generated_problems_round_trip(problem):
    assert parse_text(write(problem)) == problem
