"""Sphinx directives of the sphib documentation.

```{sphib-keys}
```
    the table of every scene key from `sphib keys --json` (the command named by the configuration
    value sphib_binary): name, type, default, allowed range and meaning, one table per section
    (the part of the name before the first dot).
"""
import json
import subprocess

from docutils import nodes
from docutils.parsers.rst import Directive
from sphinx.errors import ExtensionError


def _keys(binary):
    try:
        out = subprocess.run([binary, "keys", "--json"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise ExtensionError(f"sphib-keys: `{binary} keys --json` failed ({e}); build sphib first") from e
    return json.loads(out)


def _text(value):
    if value is None:
        return ""
    return json.dumps(value) if not isinstance(value, str) else '"%s"' % value


def _cell(text, literal=False):
    entry = nodes.entry()
    para = nodes.paragraph()
    para += nodes.literal(text=text) if literal and text else nodes.Text(text)
    entry += para
    return entry


class SceneKeys(Directive):
    has_content = False

    def run(self):
        env = self.state.document.settings.env
        keys = _keys(env.config.sphib_binary)
        sections = {}
        for k in keys:
            sections.setdefault(k["name"].split(".")[0] if "." in k["name"] else "(top level)", []).append(k)
        result = []
        for name, rows in sections.items():
            section = nodes.section(ids=["keys-" + nodes.make_id(name)])
            section += nodes.title(text=name)
            table = nodes.table(classes=["sphib-keys"])
            group = nodes.tgroup(cols=5)
            for width in (18, 12, 12, 14, 44):
                group += nodes.colspec(colwidth=width)
            head = nodes.thead()
            row = nodes.row()
            for title in ("key", "type", "default", "allowed", "meaning"):
                row += _cell(title)
            head += row
            group += head
            body = nodes.tbody()
            for k in rows:
                row = nodes.row()
                row += _cell(k["name"], literal=True)
                row += _cell(k["type"])
                row += _cell("(required)" if k["required"] else _text(k["default"]), literal=not k["required"])
                row += _cell(k["range"])
                row += _cell(k["help"])
                body += row
            group += body
            table += group
            section += table
            result.append(section)
        return result


def setup(app):
    app.add_config_value("sphib_binary", "../build/sphib", "env")
    app.add_directive("sphib-keys", SceneKeys)
    return {"version": "1", "parallel_read_safe": True}
