"""The scripted reference policy (privileged task state -> actions) and its success table."""
