"""One page's session, independent of the view: lesson, values, stepper, playback and its pace."""
