"""One table of a bench script's results, written as CSV and as Markdown (PREFIX.csv, PREFIX.md)."""
import csv


def write(prefix, title, text, rows, keys=None):
    """rows: dicts of strings; keys: the columns (default: the first row's); text: the Markdown
    between the title and the table."""
    keys = keys or list(rows[0].keys())
    with open(prefix + ".csv", "w", newline="") as f:
        out = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        out.writeheader()
        out.writerows(rows)
    with open(prefix + ".md", "w") as f:
        f.write("# %s\n\n%s\n\n" % (title, text.strip()))
        f.write("| " + " | ".join(keys) + " |\n|" + "---|" * len(keys) + "\n")
        for row in rows:
            f.write("| " + " | ".join(str(row[k]) for k in keys) + " |\n")
    print("wrote %s.md (%d rows)" % (prefix, len(rows)))
