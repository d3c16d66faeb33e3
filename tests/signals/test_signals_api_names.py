"""``dir(odnn_sep.signals)`` lists the generators it loads lazily (an editor's completion lists dir())."""
import odnn_sep.signals as signals


def test_dir_lists_every_public_name():
    names = set(dir(signals))
    assert set(signals.__all__) <= names
    for n in signals.__all__:
        assert getattr(signals, n) is not None
