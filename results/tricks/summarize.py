"""Print the held-out table of the users' tricks from the JSON files commands.sh writes:
    python results/tricks/summarize.py [NAME ...]"""
import json
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PARTS = (("anchored-only", "anchored, no self-play"), ("learned", "anchored + learned"), ("basis", "basis operators"))


def row(name: str, part: str, title: str) -> str:
    path = os.path.join(HERE, name, f"{part}.json")
    if not os.path.exists(path):
        return f"| {name} | {title} | - | - | - |"
    runs = json.load(open(path))
    solved = [r for r in runs if r["status"] == "solved"]
    times = sorted(r["time_s"] if r["status"] == "solved" else float("inf") for r in runs)
    values = [sum(r["samples"].values()) for r in solved]
    median_values = statistics.median(values) if values else "-"
    median_time = statistics.median(times)
    shown = f"{median_time:.2f}" if median_time != float("inf") else "> 120"
    return f"| {name} | {title} | {len(solved)}/{len(runs)} | {shown} | {median_values} |"


if __name__ == "__main__":
    names = sys.argv[1:] or sorted(n for n in os.listdir(HERE) if os.path.isdir(os.path.join(HERE, n)))
    print("| trick | samplers | solved (120 s) | median s | median values drawn (solved) |")
    print("|---|---|---|---|---|")
    for name in names:
        for part, title in PARTS:
            print(row(name, part, title))
