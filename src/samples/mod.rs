//! Sample scene generators: synthetic thin-film particle clouds (bubbles, films).
