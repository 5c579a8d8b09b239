"""What setup.cfg cannot say: the repository's data folders (assets/, domains/, problems/)
stay where they are in the checkout and go into the wheel as package data under
`pdsketch_mech/data/` (read through `pdsketch_mech/util/data.py`)."""
from setuptools import find_packages, setup

DATA = {"pdsketch_mech.data.assets": "assets",
        "pdsketch_mech.data.domains": "domains",
        "pdsketch_mech.data.problems": "problems"}

setup(packages=find_packages(include=["pdsketch_mech", "pdsketch_mech.*"]) + list(DATA),
      package_dir=DATA,
      package_data={"pdsketch_mech.lang": ["grammar.lark"], **{package: ["**/*"] for package in DATA}})
