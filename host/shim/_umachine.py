# umachine, as older drivers import machine: the shim's machine, imported on first use
# (an alias made at start would cost every firmware the machine module's heap).
def __getattr__(name):
    import machine

    return getattr(machine, name)
