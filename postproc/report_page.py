"""The report's page: its table cells (Html: a cell that is HTML already), the Report that
collects the HTML parts, embeds figures as data URIs and writes each table's CSV, and the page's
style and self-check script (read back by tests/analysis/check_report_chromium.py)."""
import base64
import csv
import html
import os
import re


class Html(str):
    """A table cell that is HTML already (e.g. an interval in its checkable span)."""


def plain(cell):
    """A cell as CSV text: the HTML's text."""
    if isinstance(cell, Html):
        return html.unescape(re.sub(r"<[^>]+>", "", cell))
    return cell


def cell_html(c):
    return c if isinstance(c, Html) else html.escape(str(c))


class Report:

    def __init__(self, out):
        self.out = out
        self.parts = []
        self.figures = 0
        self.csvs = []
        os.makedirs(out, exist_ok=True)

    def h(self, s):
        self.parts.append(s)

    def fig(self, name, caption):
        """Embeds OUT/name (written already) as a data URI, so the page stands alone."""
        with open(os.path.join(self.out, name), "rb") as fh:
            data = base64.b64encode(fh.read()).decode()
        self.figures += 1
        self.h(f'<figure><img alt="{html.escape(name)}" src="data:image/png;base64,{data}">'
               f'<figcaption>Fig. {self.figures}. {caption} <a href="{html.escape(name)}">'
               f'{html.escape(name)}</a></figcaption></figure>')

    def table(self, header, rows, csv_name=None):
        self.h("<table><tr>" + "".join(f"<th>{html.escape(str(c))}</th>" for c in header) + "</tr>")
        for r in rows:
            self.h("<tr>" + "".join(f"<td>{cell_html(c)}</td>" for c in r) + "</tr>")
        self.h("</table>")
        if csv_name:
            self.csv(csv_name, header, [[plain(c) for c in r] for r in rows])

    def csv(self, name, header, rows):
        with open(os.path.join(self.out, name), "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(header)
            w.writerows(rows)
        if name not in self.csvs:
            self.csvs.append(name)


CSS = """body{font-family:sans-serif;max-width:1200px;margin:1em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;margin:0.5em 0;font-size:0.85em}
td,th{border:1px solid #bbb;padding:2px 6px;text-align:left;vertical-align:top}
th{background:#eee} figure{margin:1em 0} img{max-width:100%} figcaption{font-size:0.85em}
#findings{border:2px solid #4a6fa5;background:#f4f8ff;padding:0.3em 1em;margin:1em 0}
#findings li{margin:0.35em 0} .context{font-size:0.9em;color:#333}
.warn{border-left:5px solid #d68910;background:#fef5e7;padding:0.4em 0.8em;margin:0.6em 0}
pre{background:#f6f6f6;padding:0.5em;font-size:0.8em;overflow-x:auto}"""


# Sets data attributes on <body> once everything has loaded: how many images the page holds and
# how many decoded (naturalWidth > 0). tests/analysis/check_report_chromium.py reads them back from
# headless Chromium's DOM.
CHECK_SCRIPT = """<script>
window.addEventListener('load', function () {
  var imgs = document.images, ok = 0, bad = [];
  for (var i = 0; i < imgs.length; i++) {
    if (imgs[i].complete && imgs[i].naturalWidth > 0) ok++; else bad.push(imgs[i].alt);
  }
  document.body.setAttribute('data-images-total', String(imgs.length));
  document.body.setAttribute('data-images-ok', String(ok));
  document.body.setAttribute('data-images-broken', bad.join('|'));
});
</script>"""
