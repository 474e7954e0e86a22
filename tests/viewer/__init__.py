"""Tests of the browser viewer: session, server and security, 3-D view, scope, pages."""
