"""The files a validation script leaves in docs/validation: its figure and its table."""
import csv
import os


def save(fig, out, name, header, rows):
    """Writes fig to OUT/NAME.png (laid out tightly) and the rows under header to OUT/NAME.csv."""
    fig.tight_layout()
    fig.savefig(os.path.join(out, f"{name}.png"), dpi=110)
    with open(os.path.join(out, f"{name}.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
