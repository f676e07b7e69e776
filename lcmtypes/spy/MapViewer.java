package lasonic.spy;

import java.awt.BorderLayout;
import java.beans.PropertyVetoException;
import javax.swing.JDesktopPane;
import javax.swing.JInternalFrame;
import javax.swing.Timer;
import javax.swing.event.InternalFrameAdapter;
import javax.swing.event.InternalFrameEvent;
import lcm.spy.ChannelData;

/**
 * The window a lasonic plugin opens in lcm-spy: shows the newest message of one channel.
 *
 * <p>It takes the messages lcm-spy itself has decoded ({@code ChannelData.last}, set for every
 * message received) ten times a second, instead of subscribing on its own: lcm-spy was started
 * with the user's {@code --lcm-url} (lasonic's needs {@code recv_buf_size} for grid maps), which
 * a plugin cannot see, and a second LCM instance would join the multicast group once more.
 */
public class MapViewer extends JInternalFrame {
  private static final long serialVersionUID = 1L;

  private final ChannelData cd;
  private final MapPanel panel;
  private final Timer timer;
  private Object shown;
  private long messages;
  private boolean wasShowing;

  public MapViewer(String what, ChannelData cd, MapPanel panel) {
    super(what + ": " + cd.name, true, true, true, true);
    this.cd = cd;
    this.panel = panel;
    setLayout(new BorderLayout());
    add(panel, BorderLayout.CENTER);
    setSize(500, 400);
    setVisible(true);
    timer = new Timer(100, e -> refresh());
    addInternalFrameListener(new InternalFrameAdapter() {
      @Override public void internalFrameClosed(InternalFrameEvent e) { timer.stop(); }
    });
    refresh();
    timer.start();
  }

  /** Opens a viewer filling the desktop lcm-spy gives a plugin (lcm-spy: a 500 x 400 window). */
  public static MapViewer open(JDesktopPane desktop, String what, ChannelData cd, MapPanel panel) {
    MapViewer v = new MapViewer(what, cd, panel);
    desktop.add(v);
    try {
      v.setMaximum(true);
    } catch (PropertyVetoException e) {
      // not maximised: it keeps its 500 x 400
    }
    v.toFront();
    return v;
  }

  /** Takes lcm-spy's newest message of the channel if it is new; true if it was. */
  public boolean refresh() {
    if (isShowing()) wasShowing = true;
    else if (wasShowing) {
      // lcm-spy hides (does not dispose) a plugin's window when it is closed: stop polling.
      timer.stop();
      return false;
    }
    Object m = cd.last;
    if (m == null || m == shown) return false;
    shown = m;
    messages++;
    panel.setMessage(m);
    panel.repaint();
    return true;
  }

  public MapPanel panel() { return panel; }

  /** Messages taken so far. */
  public long messages() { return messages; }
}
