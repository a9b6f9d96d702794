"""The spec checker's tools: every problem collected with its key path and its line in the
file, raised together as one ``SpecError``, and the checks of plain values."""
import yaml


class SpecError(ValueError):
    """A spec that cannot run: every problem found, one per line, each with its key and line."""

    def __init__(self, path, problems):
        self.problems = list(problems)
        lines = "\n".join(f"  {p}" for p in self.problems)
        super().__init__(f"{path}: {len(self.problems)} problem(s) in the experiment spec:\n"
                         f"{lines}")


class Lines:
    """Line numbers of every key path in a YAML document (composed, not constructed)."""

    def __init__(self, text):
        self.lines = {}
        node = yaml.compose(text)
        if node is not None:
            self._walk(node, ())

    def _walk(self, node, path):
        self.lines[path] = node.start_mark.line + 1
        if isinstance(node, yaml.MappingNode):
            for key, value in node.value:
                sub = path + (str(key.value),)
                self._walk(value, sub)
                self.lines[sub] = key.start_mark.line + 1
        elif isinstance(node, yaml.SequenceNode):
            for i, item in enumerate(node.value):
                self._walk(item, path + (i,))

    def of(self, path):
        path = tuple(path)
        while path and path not in self.lines:
            path = path[:-1]
        return self.lines.get(path, 1)


class Problems:
    """The problems found so far, each with its key path and line."""

    def __init__(self, lines):
        self.lines, self.items = lines, []

    def add(self, path, message):
        where = ".".join(str(p) for p in path) or "(top)"
        self.items.append(f"line {self.lines.of(path)}: '{where}': {message}")


def positive(raw, key, default, problems):
    value = raw.get(key, default)
    if value is None:
        if key == "duration_s":
            problems.add((key,), "required: the simulated seconds of each run")
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
        problems.add((key,), f"must be a positive number of seconds, got {value!r}")
        return None
    return float(value)


def string_list(raw, key, problems):
    value = raw.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        problems.add((key,), "must be a list of topic names or glob patterns")
        return []
    return value


def scalar_map(value, path, problems):
    if not isinstance(value, dict):
        problems.add(path, "must be a mapping of names to values")
        return {}
    for k, v in value.items():
        if isinstance(v, (dict, list)) or v is None:
            problems.add(path + (k,), "must be a single value (string, number or boolean)")
    return {str(k): v for k, v in value.items()}
