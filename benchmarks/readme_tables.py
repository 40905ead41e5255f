"""Put the latest measured tables into the README, between their markers: the maintainers' `make
refresh-readme` (after `make bench` and `make calibrate`, which write only under results/)."""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TABLES = {"bench-scale": ROOT / "results/bench/scale.md",
          "bench-imports": ROOT / "results/bench/imports.md",
          "bench-workprecision": ROOT / "results/bench/workprecision.md",
          "bench-peer": ROOT / "results/bench/peer_pyharm.md",
          "calibrate": ROOT / "results/calibration/summary.md"}


def main():
    readme = ROOT / "README.md"
    text = readme.read_text()
    for name, path in TABLES.items():
        start, end = f"<!-- {name} -->", f"<!-- /{name} -->"
        if start not in text or not path.exists():
            continue
        head, rest = text.split(start, 1)
        _, tail = rest.split(end, 1)
        body = path.read_text().strip()
        if body.startswith("# "):  # drop the file's own title
            body = body.split("\n", 1)[1].strip()
        text = f"{head}{start}\n{body}\n{end}{tail}"
    readme.write_text(text)
    print(f"updated {readme}")


if __name__ == "__main__":
    main()
