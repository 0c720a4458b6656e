pytest_plugins = ["ecatslave.pytest_plugin"]
