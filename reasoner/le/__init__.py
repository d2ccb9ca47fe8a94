"""The Logical English compiler: lexer, templates, sentences, documents, rendering."""
