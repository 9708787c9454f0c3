"""``nonideal examples``."""

from __future__ import annotations

from ..errors import ModelError, did_you_mean


def add_parser(sub, ctx) -> None:
    x = sub.add_parser("examples", help="the gallery of worked examples",
                       description="The gallery of worked examples: list, show NAME, run NAME.")
    x.add_argument("action", choices=["list", "show", "run"])
    x.add_argument("name", nargs="?")
    x.set_defaults(func=run)


def run(args) -> int:
    from .. import gallery

    if args.action == "list":
        if args.name is not None:
            name = args.name if args.name in gallery.names() else "NAME"
            raise ModelError(f"examples list takes no name (got '{args.name}'); to see one "
                             f"example: nonideal examples show {name}")
        names = gallery.names()
        width = max(len(n) for n in names) + 2
        for name in names:
            print(f"{name:{width}}{gallery.info(name).title}")
        return 0
    if not args.name:
        raise ModelError(f"examples {args.action}: give the example's name (see 'nonideal examples list')")
    if args.name not in gallery.names():
        raise ModelError(f"examples: no example '{args.name}'{did_you_mean(args.name, gallery.names())}"
                         "; see 'nonideal examples list'")
    mod = gallery.module(args.name)
    if args.action == "show":
        print(mod.__doc__.strip())
        print()
        print(f"# model file: {gallery.model_path(args.name)}")
        print(gallery.model_path(args.name).read_text())
        return 0
    result = gallery.run(args.name, verbose=True)
    return 0 if result.get("ok", True) else 1
