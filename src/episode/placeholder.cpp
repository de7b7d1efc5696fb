// replaced by the module sources
